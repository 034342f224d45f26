// Grouping the input's triangles by what glTF cannot vary per texel (see draw_split.h).
//   1. each triangle's key: per selection, the values its material fixes (a value the material
//      does not care about, e.g. attenuation without a volume, is free);
//   2. distinct keys, most fixed values first, then by area, join the first group they agree with;
//   3. above maxDraws, the smallest group merges into its nearest;
//   4. each group's values: mergeUniforms over its materials, per selection.
#include "lodbake/bake/draw_split.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <sstream>
#include <type_traits>

namespace lodbake {
namespace {

// A property glTF cannot vary per texel: its mean over the materials `has` holds for, weighted by
// area, and a warning naming it when they disagree. V is double or Vec3 (spread: the largest
// component difference). None has it: `fallback`.
template <class V, class HasFn, class ValueFn>
V uniformProperty(const std::vector<WeightedMaterial>& mats, const char* name, HasFn has, ValueFn value, V fallback,
                  std::vector<std::string>* warnings) {
    V sum{}, lo{}, hi{};
    double area = 0;
    bool first = true;
    size_t n = 0;
    for (const WeightedMaterial& u : mats) {
        if (!has(*u.material)) continue;
        const V v = value(*u.material);
        // Materials of zero area still count, equally, so the mean is defined.
        const double w = u.area > 0 ? u.area : 1e-300;
        sum = sum + v * w;
        area += w;
        if constexpr (std::is_same_v<V, double>) {
            lo = first ? v : std::min(lo, v);
            hi = first ? v : std::max(hi, v);
        } else {
            lo = first ? v : Vec3{std::min(lo.x, v.x), std::min(lo.y, v.y), std::min(lo.z, v.z)};
            hi = first ? v : Vec3{std::max(hi.x, v.x), std::max(hi.y, v.y), std::max(hi.z, v.z)};
        }
        first = false;
        ++n;
    }
    if (n == 0) return fallback;
    double spread;
    if constexpr (std::is_same_v<V, double>) spread = hi - lo;
    else spread = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z});
    if (!(spread > 0)) return lo;  // agreeing inputs: their value exactly
    const V mean = sum * (1 / area);
    if (warnings) {
        std::ostringstream w;
        w << "materials disagree on " << name << " (spread " << spread << "): the chain's material takes the area-weighted mean ";
        if constexpr (std::is_same_v<V, double>) w << mean;
        else w << "[" << mean.x << ", " << mean.y << ", " << mean.z << "]";
        warnings->push_back(w.str());
    }
    return mean;
}

bool transmits(const Material& m) { return !m.unlit && m.ext.transmission.present && m.ext.transmission.factor > 0; }

// Step 1's key: one optional value per property and selection; nullopt = free. Attenuation
// distance enters as its coefficient 1 / distance (0 = none), its colour as three values.
using Key = std::vector<std::optional<double>>;
constexpr size_t kFields = 11;  // blend, cutoff, unlit, ior, attenuation coefficient, colour r g b, dispersion, iridescence ior, transmits

void appendKey(const Material& m, bool extensionProperties, Key& key) {
    using O = std::optional<double>;
    const bool blend = m.alphaMode == AlphaMode::Blend;
    key.push_back(blend ? 1.0 : 0.0);
    // An OPAQUE material is baked with alpha 1, which passes every cutoff: it may join a MASK group.
    key.push_back(m.alphaMode == AlphaMode::Mask ? O(m.alphaCutoff) : std::nullopt);
    key.push_back(m.unlit ? 1.0 : 0.0);
    if (m.unlit || !extensionProperties) {  // the lit properties do not show
        key.insert(key.end(), kFields - 3, std::nullopt);
        return;
    }
    const MaterialExtensions& e = m.ext;
    key.push_back(e.ior.present ? e.ior.ior : IorExtension{}.ior);
    // Without a volume the part is thin-walled: attenuation and dispersion do not show.
    if (e.volume.present) {
        const double d = e.volume.attenuationDistance;
        key.push_back(std::isfinite(d) ? 1 / d : 0.0);
        key.push_back(e.volume.attenuationColor.x);
        key.push_back(e.volume.attenuationColor.y);
        key.push_back(e.volume.attenuationColor.z);
        key.push_back(e.dispersion.present ? e.dispersion.dispersion : 0.0);
    } else {
        key.insert(key.end(), 5, std::nullopt);
    }
    key.push_back(e.iridescence.present ? O(e.iridescence.ior) : std::nullopt);
    key.push_back(transmits(m) ? 1.0 : 0.0);
}

size_t fixedCount(const Key& k) { return size_t(std::count_if(k.begin(), k.end(), [](const auto& v) { return v.has_value(); })); }

// Fields both fix to different values.
size_t conflicts(const Key& a, const Key& b) {
    size_t n = 0;
    for (size_t i = 0; i < a.size(); ++i) n += a[i] && b[i] && *a[i] != *b[i] ? 1 : 0;
    return n;
}

void fillFree(Key& into, const Key& from) {
    for (size_t i = 0; i < into.size(); ++i)
        if (!into[i]) into[i] = from[i];
}

struct Group {
    Key key;              // the values its members fix
    double area = 0;
    std::vector<size_t> keys;  // indices of the distinct keys it holds
};

}  // namespace

MaterialUniforms mergeUniforms(const std::vector<WeightedMaterial>& mats, std::vector<std::string>* warnings, const MaterialUniforms* unseen) {
    MaterialUniforms u;
    bool anyMask = false, anyBlend = false, anyOpaque = false, anyUnlit = false, allUnlit = true;
    bool anyTransmits = false, anyLitSolid = false;
    double cutoff = 1;
    for (const WeightedMaterial& w : mats) {
        const Material& m = *w.material;
        anyUnlit |= m.unlit;
        allUnlit &= m.unlit;
        anyMask |= m.alphaMode == AlphaMode::Mask;
        anyBlend |= m.alphaMode == AlphaMode::Blend;
        anyOpaque |= m.alphaMode == AlphaMode::Opaque;
        if (m.alphaMode == AlphaMode::Mask) cutoff = std::min(cutoff, m.alphaCutoff);
        anyTransmits |= transmits(m);
        anyLitSolid |= !m.unlit && !transmits(m);
    }
    u.alphaMode = anyBlend ? AlphaMode::Blend : anyMask ? AlphaMode::Mask : AlphaMode::Opaque;
    u.alphaCutoff = anyMask ? cutoff : 0.5;
    u.unlit = !mats.empty() && allUnlit;
    if (warnings) {
        if ((anyMask || anyBlend) && anyOpaque)
            warnings->push_back("materials mix alpha modes: opaque parts are baked with alpha 1 into one " +
                                std::string(anyBlend ? "BLEND" : "MASK") + " material");
        if (anyMask && anyBlend) warnings->push_back("materials mix MASK and BLEND: the chain's material blends");
        if (anyUnlit && !allUnlit) warnings->push_back("materials mix unlit and lit shading: the chain's material is lit");
    }
    if (u.unlit) return u;
    u.transmission = anyTransmits;
    if (warnings && anyTransmits && anyLitSolid)
        warnings->push_back("materials mix transmissive and solid parts in one primitive: renderers that refract only "
                            "the opaque pass (three.js, Babylon.js) show nothing of the solid parts through the transmissive ones");
    auto volume = [](const Material& m) { return m.ext.volume.present; };
    const MaterialUniforms defaults = unseen ? *unseen : MaterialUniforms{};
    // Attenuation is exponential in distance / attenuationDistance: its coefficient
    // 1 / distance is what averages (an infinite distance, no attenuation, is 0).
    const double coefficient = uniformProperty<double>(
        mats, "KHR_materials_volume attenuationDistance (as 1 / distance)", volume,
        [](const Material& m) { return std::isfinite(m.ext.volume.attenuationDistance) ? 1 / m.ext.volume.attenuationDistance : 0.0; },
        std::isfinite(defaults.attenuationDistance) ? 1 / defaults.attenuationDistance : 0.0, warnings);
    u.attenuationDistance = coefficient > 0 ? 1 / coefficient : std::numeric_limits<double>::infinity();
    u.attenuationColor = uniformProperty<Vec3>(mats, "KHR_materials_volume attenuationColor", volume,
                                               [](const Material& m) { return m.ext.volume.attenuationColor; }, defaults.attenuationColor, warnings);
    // A lit material without KHR_materials_ior has ior 1.5, a volume without dispersion none: they
    // count with those values (as the grouping's keys do).
    u.ior = uniformProperty<double>(mats, "KHR_materials_ior ior", [](const Material& m) { return !m.unlit; },
                                    [](const Material& m) { return m.ext.ior.present ? m.ext.ior.ior : IorExtension{}.ior; },
                                    IorExtension{}.ior, warnings);
    u.dispersion = uniformProperty<double>(mats, "KHR_materials_dispersion dispersion", volume,
                                           [](const Material& m) { return m.ext.dispersion.present ? m.ext.dispersion.dispersion : 0.0; },
                                           defaults.dispersion, warnings);
    u.iridescenceIor = uniformProperty<double>(mats, "KHR_materials_iridescence iridescenceIor",
                                               [](const Material& m) { return m.ext.iridescence.present; },
                                               [](const Material& m) { return m.ext.iridescence.ior; }, defaults.iridescenceIor, warnings);
    return u;
}

DrawSplit splitDraws(const Asset& asset, const std::vector<const std::vector<int32_t>*>& selections, const DrawSplitOptions& options) {
    const TriMesh& mesh = asset.mesh;
    const size_t triangles = mesh.triangleCount();
    static const Material kDefault;
    auto material = [&](int32_t i) -> const Material& {
        return i >= 0 && size_t(i) < asset.materials.size() ? asset.materials[size_t(i)] : kDefault;
    };
    std::vector<double> area(triangles);
    for (size_t t = 0; t < triangles; ++t) {
        const Tri& tri = mesh.triangles[t];
        area[t] = 0.5 * length(cross(mesh.positions[tri[1]] - mesh.positions[tri[0]], mesh.positions[tri[2]] - mesh.positions[tri[0]]));
    }
    // 1. Distinct keys (ordered, so everything below is deterministic) and their areas.
    std::map<Key, size_t> keyIndex;
    std::vector<Key> keys;
    std::vector<double> keyArea;
    std::vector<size_t> keyOf(triangles);
    for (size_t t = 0; t < triangles; ++t) {
        Key k;
        for (const std::vector<int32_t>* s : selections) appendKey(material((*s)[t]), options.extensionProperties, k);
        auto [it, inserted] = keyIndex.emplace(k, keys.size());
        if (inserted) {
            keys.push_back(std::move(k));
            keyArea.push_back(0);
        }
        keyOf[t] = it->second;
        keyArea[it->second] += area[t];
    }
    // 2. Most fixed values first (a free value then joins a group that fixes it), then the largest.
    std::vector<size_t> order(keys.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
        const size_t fa = fixedCount(keys[a]), fb = fixedCount(keys[b]);
        return fa != fb ? fa > fb : keyArea[a] > keyArea[b];
    });
    std::vector<Group> groups;
    for (size_t k : order) {
        Group* g = nullptr;
        for (Group& c : groups)
            if (conflicts(c.key, keys[k]) == 0) {
                g = &c;
                break;
            }
        if (!g) {
            groups.push_back({keys[k], 0, {}});
            g = &groups.back();
        }
        fillFree(g->key, keys[k]);
        g->area += keyArea[k];
        g->keys.push_back(k);
    }
    // 3. Too many: the smallest merges into the one it conflicts with least (then the largest).
    while (options.maxDraws > 0 && groups.size() > options.maxDraws) {
        size_t small = 0;
        for (size_t i = 1; i < groups.size(); ++i)
            if (groups[i].area <= groups[small].area) small = i;
        size_t into = small == 0 ? 1 : 0;
        for (size_t i = 0; i < groups.size(); ++i) {
            if (i == small) continue;
            const size_t ci = conflicts(groups[i].key, groups[small].key), cb = conflicts(groups[into].key, groups[small].key);
            if (ci < cb || (ci == cb && groups[i].area > groups[into].area)) into = i;
        }
        Group& to = groups[into];
        fillFree(to.key, groups[small].key);
        to.area += groups[small].area;
        to.keys.insert(to.keys.end(), groups[small].keys.begin(), groups[small].keys.end());
        groups.erase(groups.begin() + std::ptrdiff_t(small));
    }
    DrawSplit out;
    out.warnings.resize(selections.size());
    std::vector<uint32_t> groupOfKey(keys.size());
    for (size_t g = 0; g < groups.size(); ++g)
        for (size_t k : groups[g].keys) groupOfKey[k] = uint32_t(g);
    out.groupOf.resize(triangles);
    for (size_t t = 0; t < triangles; ++t) out.groupOf[t] = groupOfKey[keyOf[t]];
    // 4. Per group and selection: its used materials (in index order, as the plan lists them) and
    // their areas.
    out.groups.resize(std::max<size_t>(groups.size(), 1));
    // A property no material of a group shows (attenuation without a volume, ...) takes the
    // selection's merged value, so the parts' materials differ only where they must.
    for (size_t s = 0; s < selections.size(); ++s) {
        std::vector<std::map<int32_t, double>> used(out.groups.size());
        std::map<int32_t, double> all;
        for (size_t t = 0; t < triangles; ++t) {
            used[out.groupOf[t]][(*selections[s])[t]] += area[t];
            all[(*selections[s])[t]] += area[t];
        }
        std::vector<WeightedMaterial> mats;
        for (const auto& [index, a] : all) mats.push_back({&material(index), a});
        const MaterialUniforms merged = mergeUniforms(mats, nullptr);
        for (size_t g = 0; g < out.groups.size(); ++g) {
            mats.clear();
            for (const auto& [index, a] : used[g]) mats.push_back({&material(index), a});
            out.groups[g].values.push_back(mergeUniforms(mats, &out.warnings[s], &merged));
        }
    }
    for (size_t g = 0; g < groups.size(); ++g) out.groups[g].area = groups[g].area;
    for (size_t a = 0; a < out.groups.size(); ++a)
        for (size_t b = a + 1; b < out.groups.size(); ++b)
            for (size_t s = 0; s < selections.size(); ++s)
                for (const std::string& d : uniformDifferences(out.groups[a].values[s], out.groups[b].values[s]))
                    if (std::find(out.splitBy.begin(), out.splitBy.end(), d) == out.splitBy.end()) out.splitBy.push_back(d);
    return out;
}

}  // namespace lodbake
