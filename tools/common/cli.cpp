#include "common/cli.h"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <stdexcept>


namespace lodbake::cli {

namespace {

std::vector<std::string> splitNames(const std::string& names) {
    std::vector<std::string> out;
    std::stringstream ss(names);
    std::string n;
    while (std::getline(ss, n, ',')) {
        while (!n.empty() && n.front() == ' ') n.erase(n.begin());
        if (!n.empty()) out.push_back(n);
    }
    return out;
}

std::string lowerExtension(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return ext;
}

}  // namespace

ArgParser::ArgParser(std::string tool, std::string synopsis)
    : tool_(std::move(tool)), synopsis_(std::move(synopsis)) {}

void ArgParser::add(Opt opt) {
    // A name given twice would silently bind to one of the two handlers.
    for (const Opt& o : opts_)
        for (const std::string& n : o.names)
            if (std::find(opt.names.begin(), opt.names.end(), n) != opt.names.end())
                throw std::logic_error(tool_ + ": flag " + n + " is defined twice");
    opt.section = std::move(pendingSection_);
    opt.sectionIntro = std::move(pendingIntro_);
    pendingSection_.clear();
    pendingIntro_.clear();
    opts_.push_back(std::move(opt));
}

ArgParser::Opt* ArgParser::find(const std::string& name) {
    for (Opt& o : opts_)
        if (std::find(o.names.begin(), o.names.end(), name) != o.names.end()) return &o;
    return nullptr;
}

const ArgParser::Opt* ArgParser::find(const std::string& name) const {
    return const_cast<ArgParser*>(this)->find(name);
}

void ArgParser::option(const std::string& names, const std::string& valueName, const std::string& help,
                       std::function<void(const std::string&)> handler) {
    add({splitNames(names), valueName, help, std::move(handler), true, {}, {}});
}

void ArgParser::flag(const std::string& names, const std::string& help, std::function<void()> handler) {
    add({splitNames(names), "", help, [h = std::move(handler)](const std::string&) { h(); }, false, {}, {}});
}

void ArgParser::section(const std::string& title, const std::string& intro) {
    pendingSection_ = title;
    pendingIntro_ = intro;
}

void ArgParser::featured(const std::string& title, const std::vector<std::string>& names) {
    featuredTitle_ = title;
    featured_ = names;
}

void ArgParser::describe(const std::string& name, const std::string& help) {
    Opt* o = find(name);
    if (!o) throw std::logic_error(tool_ + ": describe: no flag " + name);
    o->help = help;
}

void ArgParser::positionals(const std::string& names, std::function<void(const std::string&)> handler) {
    positionalNames_ = names;
    positional_ = std::move(handler);
}

void ArgParser::addCommon(StageCommon& s, bool& quiet, bool needsOutput) {
    option("-i,--input", "FILE", "input glTF (.gltf or .glb)", [&s](const std::string& v) { s.input = v; });
    if (needsOutput)
        option("-o,--output", "FILE", "output file; .glb or .gltf (+ .bin) chosen by its extension",
               [&s](const std::string& v) { s.output = v; });
    option("--report", "FILE.json", "write the JSON report to FILE.json", [&s](const std::string& v) { s.report = v; });
    flag("-v", "print statistics on stdout", [&s] { s.verbose = std::max(s.verbose, 1); });
    flag("-vv", "print more statistics on stdout", [&s] { s.verbose = 2; });
    option("--threads", "N", "worker threads (default 0 = all cores); output is identical for any N",
           [&s](const std::string& v) {
               s.threads = parseInt("--threads", v);
               if (s.threads < 0) throw UsageError("--threads must be >= 0");
           });
    flag("-q,--quiet", "no progress on stderr, even on a terminal", [&quiet] { quiet = true; });
}

bool ArgParser::parse(int argc, char** argv) {
    for (int i = 1; i < argc; ++i) {
        std::string a = argv[i];
        if (a == "-h" || a == "--help") {
            std::cout << help();
            return false;
        }
        if (a == "--version") {
            std::cout << tool_ << " (lodbake) 0.1.0\n";
            return false;
        }
        std::string value;
        bool hasInline = false;
        if (a.rfind("--", 0) == 0) {
            size_t eq = a.find('=');
            if (eq != std::string::npos) {
                value = a.substr(eq + 1);
                a = a.substr(0, eq);
                hasInline = true;
            }
        }
        const Opt* found = nullptr;
        for (const Opt& o : opts_)
            for (const std::string& n : o.names)
                if (n == a) found = &o;
        if (found) parsed_.emplace_back(size_t(found - opts_.data()), std::string());
        if (!found) {
            if ((a.empty() || a[0] != '-' || a == "-") && positional_) {
                positional_(a);
                continue;
            }
            throw UsageError("unrecognized option '" + a + "'");
        }
        if (found->takesValue) {
            if (!hasInline) {
                if (i + 1 >= argc) throw UsageError("option '" + a + "' needs a value (" + found->valueName + ")");
                value = argv[++i];
            }
            parsed_.back().second = value;
            found->handler(value);
        } else {
            if (hasInline) throw UsageError("option '" + a + "' takes no value");
            found->handler("");
        }
    }
    return true;
}

std::vector<std::string> ArgParser::argumentsExcept(const std::vector<std::string>& except) const {
    std::vector<std::string> out;
    for (const auto& [index, value] : parsed_) {
        const Opt& o = opts_[index];
        bool skip = false;
        for (const std::string& n : o.names) skip = skip || std::find(except.begin(), except.end(), n) != except.end();
        if (skip) continue;
        out.push_back(o.names.back());
        if (o.takesValue) out.push_back(value);
    }
    return out;
}

namespace {

constexpr size_t kHelpIndent = 30;  // column where the help texts start
constexpr size_t kHelpWidth = 100;  // help texts are wrapped at this column

// "  -o, --output FILE         text", the text wrapped at kHelpWidth with its lines indented.
std::string helpLine(const std::vector<std::string>& names, const std::string& valueName, bool takesValue, const std::string& text) {
    std::string left = "  ";
    for (size_t k = 0; k < names.size(); ++k) left += (k ? ", " : "") + names[k];
    if (takesValue) left += " " + valueName;
    std::string out = left;
    size_t column = left.size();
    if (column + 2 > kHelpIndent) {
        out += "\n";
        column = 0;
    }
    std::istringstream words(text);
    bool first = true;
    for (std::string w; words >> w; first = false) {
        if (!first && column + 1 + w.size() > kHelpWidth) {
            out += "\n";
            column = 0;
        }
        if (column < kHelpIndent) {
            out += std::string(kHelpIndent - column, ' ');
            column = kHelpIndent;
        } else {
            out += ' ';
            ++column;
        }
        out += w;
        column += w.size();
    }
    return out + "\n";
}

}  // namespace

std::string ArgParser::help() const {
    std::ostringstream os;
    os << "Usage: " << tool_ << " " << synopsis_ << "\n";
    auto line = [](const Opt& o) { return helpLine(o.names, o.valueName, o.takesValue, o.help); };
    std::vector<const Opt*> first;
    for (const std::string& name : featured_) {
        const Opt* o = find(name);
        if (!o) throw std::logic_error(tool_ + ": featured flag " + name + " is not defined");
        first.push_back(o);
    }
    if (!first.empty()) {
        os << "\n" << featuredTitle_ << ":\n";
        for (const Opt* o : first) os << line(*o);
    }
    os << "\n" << (first.empty() ? "Options" : "Other options") << ":\n";
    for (const Opt& o : opts_) {
        if (!o.section.empty()) {
            if (!o.sectionIntro.empty()) os << "\n" << o.sectionIntro << "\n";
            os << "\n" << o.section << ":\n";
        }
        if (std::find(first.begin(), first.end(), &o) == first.end()) os << line(o);
    }
    os << helpLine({"-h", "--help"}, "", false, "show this help") << helpLine({"--version"}, "", false, "print the version")
       << "\n"
       << exitCodes_;
    return os.str();
}

double parseDouble(const std::string& flag, const std::string& v) {
    char* end = nullptr;
    errno = 0;
    double d = std::strtod(v.c_str(), &end);
    if (v.empty() || *end != '\0' || errno == ERANGE || !std::isfinite(d))
        throw UsageError(flag + ": '" + v + "' is not a number");
    return d;
}

int parseInt(const std::string& flag, const std::string& v) {
    char* end = nullptr;
    errno = 0;
    long n = std::strtol(v.c_str(), &end, 10);
    if (v.empty() || *end != '\0' || errno == ERANGE || n < -2147483647L || n > 2147483647L)
        throw UsageError(flag + ": '" + v + "' is not an integer");
    return static_cast<int>(n);
}

std::vector<double> parseDoubleList(const std::string& flag, const std::string& v) {
    std::vector<double> out;
    std::stringstream ss(v);
    std::string item;
    while (std::getline(ss, item, ',')) out.push_back(parseDouble(flag, item));
    if (out.empty()) throw UsageError(flag + ": expected a comma-separated list of numbers");
    return out;
}

std::vector<double> parseVec3(const std::string& flag, const std::string& v) {
    std::vector<double> out = parseDoubleList(flag, v);
    if (out.size() != 3) throw UsageError(flag + ": expected x,y,z");
    return out;
}

std::string number(double v) {
    std::ostringstream os;
    os << v;
    return os.str();
}

int exitCodeFor(ErrorKind kind) {
    switch (kind) {
        case ErrorKind::Usage: return kUsage;
        case ErrorKind::IO: return kBadInput;
        case ErrorKind::InvalidInput: return kBadInput;
        case ErrorKind::Unsupported: return kBadInput;
        case ErrorKind::Impossible: return kImpossible;
        case ErrorKind::Solver: return kInternal;
        case ErrorKind::Cancelled: return kInternal;
    }
    return kInternal;
}

int runTool(const std::string& tool, const std::function<int()>& body) {
    try {
        return body();
    } catch (const Error& e) {
        std::cerr << tool << " error: " << e.what();
        if (e.kind() == ErrorKind::Usage) std::cerr << ". See '" << tool << " --help'.";
        std::cerr << "\n";
        return exitCodeFor(e.kind());
    } catch (const std::bad_alloc&) {
        std::cerr << tool << " error: out of memory\n";
        return kInternal;
    } catch (const std::exception& e) {
        std::cerr << tool << " error: internal: " << e.what() << "\n";
        return kInternal;
    }
}

void checkPaths(const StageCommon& s, const std::vector<std::string>& allowedExt) {
    namespace fs = std::filesystem;
    if (s.input.empty()) throw UsageError("missing input (-i FILE)");
    if (s.output.empty()) throw UsageError("missing output (-o FILE)");
    std::string ext = lowerExtension(s.output);
    bool ok = false;
    for (const std::string& e : allowedExt) ok = ok || ext == e;
    if (!ok) {
        std::string list;
        for (const std::string& e : allowedExt) list += (list.empty() ? "" : ", ") + e;
        throw UsageError("output '" + s.output + "' must end in " + list);
    }
    std::error_code ec;
    if (!fs::exists(s.input, ec)) throw IOError(s.input + ": no such file");
    if (fs::is_directory(s.input, ec)) throw IOError(s.input + ": is a directory");
    fs::path parent = fs::path(s.output).parent_path();
    if (!parent.empty() && !fs::is_directory(parent, ec))
        throw IOError(s.output + ": output folder '" + parent.string() + "' does not exist");
    if (fs::weakly_canonical(s.input, ec) == fs::weakly_canonical(s.output, ec))
        throw UsageError("output '" + s.output + "' would overwrite the input");
    if (!s.report.empty()) {
        fs::path rp = fs::path(s.report).parent_path();
        if (!rp.empty() && !fs::is_directory(rp, ec))
            throw IOError(s.report + ": report folder '" + rp.string() + "' does not exist");
    }
}

Progress::Progress(std::string stage, bool enabled) : stage_(std::move(stage)), enabled_(enabled) {}

Progress::~Progress() { done(); }

bool Progress::operator()(double fraction) {
    if (!enabled_) return true;
    int pct = static_cast<int>(std::lround(std::clamp(fraction, 0.0, 1.0) * 100));
    if (pct != last_) {
        last_ = pct;
        std::fprintf(stderr, "\r%s: %3d%%", stage_.c_str(), pct);
        std::fflush(stderr);
    }
    return true;
}

void Progress::done() {
    if (enabled_ && last_ >= 0) {
        std::fprintf(stderr, "\r%s: done\n", stage_.c_str());
        last_ = -1;
    }
}

bool progressEnabled(bool quiet) { return !quiet && isatty(STDERR_FILENO); }

void printWarning(const std::string& tool, const std::string& message) {
    std::cerr << tool << " warning: " << message << "\n";
}

}  // namespace lodbake::cli
