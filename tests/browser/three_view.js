// Fixed physically based render setup for comparing glTF files as users see them in three.js:
// PMREM of RoomEnvironment as scene.environment, one directional light, Neutral tone mapping,
// sRGB output, transparent background, a perspective camera framing the bounding sphere of a
// reference file's vertices from `views` azimuths (every 360/views degrees) at one elevation.
//
// API for the driver (three_run.js), once window.lodbakeThreeReady is true:
//   await lodbakeSetup({size})             renderer and lights (size: square image side, pixels)
//   await lodbakeFrame(url)                frames the cameras on this file's scene
//   await lodbakeRender(url, node, views, elevationDeg, seams, variant)
//       renders the file's default scene, or only node `node` (an index, with its children,
//       and the scene's KHR_lights_punctual lights) when node >= 0, with KHR_materials_variants
//       variant `variant` selected when it is a name (null = the default materials); returns {ok, errors, width, height, views: [base64 RGBA, rows top-down,
//       RGB premultiplied by alpha = composited over black]}; with `seams`, also seams: per view
//       the visible texture seams as base64 RGBA (R = 255 on a seam pixel, same rows).
//
// A texture seam is an interior edge whose two triangles give it different TEXCOORD_0 values at
// either end (a chart boundary of an atlas): drawn as lines over the depth of the object itself,
// so only the seams a viewer can see are marked.
import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { DRACOLoader } from 'three/addons/loaders/DRACOLoader.js';
import { KTX2Loader } from 'three/addons/loaders/KTX2Loader.js';
import { RoomEnvironment } from 'three/addons/environments/RoomEnvironment.js';
import { MeshoptDecoder } from 'three/addons/libs/meshopt_decoder.module.js';

const kFovDeg = 30;
const kLightIntensity = 2.0;
const kLightDirection = new THREE.Vector3(0.5, 1.0, 0.8).normalize();  // towards the light, world space

let renderer = null;
let scene = null;
let loader = null;
let light = null;
let frame = null;  // {center: Vector3, radius}

function setup({ size }) {
  const canvas = document.getElementById('c');
  renderer = new THREE.WebGLRenderer({ canvas, antialias: true, alpha: true, preserveDrawingBuffer: true,
                                       premultipliedAlpha: true, powerPreference: 'default' });
  renderer.setPixelRatio(1);
  renderer.setSize(size, size, false);
  renderer.setClearColor(0x000000, 0);
  renderer.toneMapping = THREE.NeutralToneMapping;
  renderer.toneMappingExposure = 1.0;
  renderer.outputColorSpace = THREE.SRGBColorSpace;
  scene = new THREE.Scene();
  const pmrem = new THREE.PMREMGenerator(renderer);
  scene.environment = pmrem.fromScene(new RoomEnvironment(), 0.04).texture;
  pmrem.dispose();
  scene.background = null;
  light = new THREE.DirectionalLight(0xffffff, kLightIntensity);
  scene.add(light);
  scene.add(light.target);
  const draco = new DRACOLoader();
  draco.setDecoderPath('/three/examples/jsm/libs/draco/gltf/');
  loader = new GLTFLoader();
  loader.setDRACOLoader(draco);
  loader.setMeshoptDecoder(MeshoptDecoder);
  // KHR_texture_basisu: the Basis Universal transcoder served locally like the rest of three.js.
  const ktx2 = new KTX2Loader();
  ktx2.setTranscoderPath('/three/examples/jsm/libs/basis/');
  ktx2.detectSupport(renderer);
  loader.setKTX2Loader(ktx2);
  return { ok: true, revision: THREE.REVISION };
}

// Selects KHR_materials_variants variant `name` on `object` as a viewer's selectVariant does:
// every primitive whose mappings name the variant gets that material. three.js's GLTFLoader
// reads only the default materials (its variants live in a third-party plugin), so the
// primitives are found through the parser's associations.
async function selectVariant(gltf, object, name) {
  const json = gltf.parser.json;
  const variants = ((json.extensions || {}).KHR_materials_variants || {}).variants || [];
  const index = variants.findIndex((v) => v.name === name);
  if (index < 0) throw new Error('no variant named ' + JSON.stringify(name) + ' in the file');
  const meshes = [];
  object.traverse((o) => { if (o.isMesh) meshes.push(o); });
  for (const mesh of meshes) {
    const a = gltf.parser.associations.get(mesh);
    if (!a || a.meshes === undefined || a.primitives === undefined) continue;
    const primitive = json.meshes[a.meshes].primitives[a.primitives];
    const ext = (primitive.extensions || {}).KHR_materials_variants;
    const mapping = ext && (ext.mappings || []).find((m) => (m.variants || []).includes(index));
    if (!mapping) continue;
    mesh.material = await gltf.parser.getDependency('material', mapping.material);
    gltf.parser.assignFinalMaterial(mesh);
  }
}

async function loadObject(url, node, variant) {
  const gltf = await loader.loadAsync(url);
  let object = gltf.scene || (gltf.scenes && gltf.scenes[0]);
  if (node >= 0) {
    const count = (gltf.parser.json.nodes || []).length;
    if (node >= count) throw new Error('node ' + node + ' out of range (' + count + ' nodes)');
    object = await gltf.parser.getDependency('node', node);
    // The file's punctual lights light every level as a viewer shows them: they come along, at
    // their place in the scene, when they are not under the node already.
    const lights = [];
    if (gltf.scene) {
      gltf.scene.updateMatrixWorld(true);
      gltf.scene.traverse((o) => {
        let inside = false;
        for (let p = o; p && !inside; p = p.parent) inside = p === object;
        if (o.isLight && !inside) lights.push(o);
      });
    }
    object.removeFromParent();
    if (lights.length > 0) {
      const group = new THREE.Group();
      for (const l of lights) group.attach(l);
      group.add(object);
      object = group;
    }
  }
  if (!object) throw new Error('no scene in ' + url);
  if (variant !== undefined && variant !== null) await selectVariant(gltf, object, variant);
  return object;
}

function disposeObject(object) {
  object.traverse((o) => {
    if (o.geometry) o.geometry.dispose();
    const materials = Array.isArray(o.material) ? o.material : (o.material ? [o.material] : []);
    for (const m of materials) {
      for (const key of Object.keys(m)) if (m[key] && m[key].isTexture) m[key].dispose();
      m.dispose();
    }
  });
}

async function frameOn(url) {
  const object = await loadObject(url, -1);
  object.updateMatrixWorld(true);
  const box = new THREE.Box3().setFromObject(object, true);
  if (box.isEmpty()) throw new Error('empty bounding box in ' + url);
  const center = box.getCenter(new THREE.Vector3());
  // Radius of the smallest sphere about the box centre holding every vertex: no view clips.
  let radius2 = 0;
  const p = new THREE.Vector3();
  object.traverse((o) => {
    const position = o.geometry && o.geometry.attributes.position;
    if (!position) return;
    for (let i = 0; i < position.count; ++i) {
      p.fromBufferAttribute(position, i).applyMatrix4(o.matrixWorld);
      radius2 = Math.max(radius2, p.distanceToSquared(center));
    }
  });
  disposeObject(object);
  const radius = Math.max(Math.sqrt(radius2), 1e-6);
  frame = { center, radius };
  const at = center.clone().addScaledVector(kLightDirection, 4 * radius);
  light.position.copy(at);
  light.target.position.copy(center);
  light.updateMatrixWorld(true);
  light.target.updateMatrixWorld(true);
  return { ok: true, center: center.toArray(), radius };
}

// Interior edges of `geometry` whose two sides carry different UVs, as a line geometry in the
// mesh's own space (null when it has none). Vertices are matched by position, so a seam shows
// whether the file splits its vertices there or not.
function seamGeometry(geometry) {
  const position = geometry.attributes.position, uv = geometry.attributes.uv;
  if (!position || !uv) return null;
  const index = geometry.index;
  const count = index ? index.count : position.count;
  const corner = (i) => (index ? index.getX(i) : i);
  const keyOf = new Map();
  const key = (v) => {
    let k = keyOf.get(v);
    if (k === undefined) {
      k = position.getX(v).toPrecision(6) + ',' + position.getY(v).toPrecision(6) + ',' + position.getZ(v).toPrecision(6);
      keyOf.set(v, k);
    }
    return k;
  };
  const kUvTolerance = 1e-5;
  const edges = new Map();  // position-key pair (sorted) -> {a, b: vertices, uvs: [[ua, ub]], split}
  for (let t = 0; t + 2 < count; t += 3) {
    for (let e = 0; e < 3; ++e) {
      let a = corner(t + e), b = corner(t + (e + 1) % 3);
      let ka = key(a), kb = key(b);
      if (ka === kb) continue;
      if (ka > kb) { [a, b] = [b, a]; [ka, kb] = [kb, ka]; }
      const k = ka + '|' + kb;
      const uvs = [uv.getX(a), uv.getY(a), uv.getX(b), uv.getY(b)];
      const edge = edges.get(k);
      if (!edge) { edges.set(k, { a, b, uvs, sides: 1, split: false }); continue; }
      edge.sides += 1;
      for (let c = 0; c < 4; ++c) if (Math.abs(edge.uvs[c] - uvs[c]) > kUvTolerance) edge.split = true;
    }
  }
  const points = [];
  for (const edge of edges.values()) {
    if (!edge.split || edge.sides !== 2) continue;
    for (const v of [edge.a, edge.b]) points.push(position.getX(v), position.getY(v), position.getZ(v));
  }
  if (!points.length) return null;
  const lines = new THREE.BufferGeometry();
  lines.setAttribute('position', new THREE.Float32BufferAttribute(points, 3));
  return lines;
}

// Renders the seam mask of `object` from `camera`: the object's depth in black (cut-outs keep
// their holes), pushed back a little, then its seam lines in white on top (depth-tested: hidden
// seams stay black).
function renderSeams(object, camera) {
  const white = new THREE.LineBasicMaterial({ color: 0xffffff });
  const seamScene = new THREE.Scene();
  const owned = [white];
  object.updateMatrixWorld(true);
  object.traverse((o) => {
    // Skinned meshes are drawn posed, their seam lines would not be: they get no mask.
    if (!o.isMesh || o.isSkinnedMesh || !o.geometry) return;
    const m = Array.isArray(o.material) ? o.material[0] : o.material;
    const black = new THREE.MeshBasicMaterial({ color: 0x000000, map: (m && m.alphaTest > 0 && m.map) || null,
                                                alphaTest: (m && m.alphaTest) || 0, side: THREE.DoubleSide,
                                                polygonOffset: true, polygonOffsetFactor: 1, polygonOffsetUnits: 1 });
    owned.push(black);
    const mesh = new THREE.Mesh(o.geometry, black);
    mesh.matrixAutoUpdate = false;
    mesh.matrix.copy(o.matrixWorld);
    seamScene.add(mesh);
    const seams = seamGeometry(o.geometry);
    if (!seams) return;
    const lines = new THREE.LineSegments(seams, white);
    lines.matrixAutoUpdate = false;
    lines.matrix.copy(o.matrixWorld);
    seamScene.add(lines);
    owned.push(seams);
  });
  const toneMapping = renderer.toneMapping;
  renderer.toneMapping = THREE.NoToneMapping;
  renderer.render(seamScene, camera);
  renderer.toneMapping = toneMapping;
  for (const x of owned) x.dispose();
}

function toBase64(bytes) {
  let s = '';
  const chunk = 0x8000;
  for (let i = 0; i < bytes.length; i += chunk) s += String.fromCharCode.apply(null, bytes.subarray(i, i + chunk));
  return btoa(s);
}

async function renderViews(url, node, views, elevationDeg, seams, variant) {
  if (!frame) throw new Error('lodbakeFrame was not called');
  const object = await loadObject(url, node, variant);
  scene.add(object);
  const size = renderer.getDrawingBufferSize(new THREE.Vector2());
  const w = size.x, h = size.y;
  const fov = THREE.MathUtils.degToRad(kFovDeg);
  const distance = frame.radius / Math.sin(fov / 2);
  const camera = new THREE.PerspectiveCamera(kFovDeg, w / h, Math.max(distance - 1.5 * frame.radius, distance * 1e-3),
                                             distance + 1.5 * frame.radius);
  const elevation = THREE.MathUtils.degToRad(elevationDeg);
  const gl = renderer.getContext();
  const pixels = new Uint8Array(w * h * 4);
  const flipped = new Uint8Array(w * h * 4);
  const out = [], seamOut = [];
  const read = () => {
    gl.readPixels(0, 0, w, h, gl.RGBA, gl.UNSIGNED_BYTE, pixels);
    for (let y = 0; y < h; ++y) flipped.set(pixels.subarray((h - 1 - y) * w * 4, (h - y) * w * 4), y * w * 4);
    return toBase64(flipped);
  };
  for (let v = 0; v < views; ++v) {
    const azimuth = 2 * Math.PI * v / views;
    camera.position.set(frame.center.x + distance * Math.cos(elevation) * Math.sin(azimuth),
                        frame.center.y + distance * Math.sin(elevation),
                        frame.center.z + distance * Math.cos(elevation) * Math.cos(azimuth));
    camera.lookAt(frame.center);
    camera.updateMatrixWorld(true);
    renderer.render(scene, camera);
    out.push(read());
    if (seams) {
      renderSeams(object, camera);
      seamOut.push(read());
    }
  }
  scene.remove(object);
  disposeObject(object);
  return seams ? { ok: true, width: w, height: h, views: out, seams: seamOut } : { ok: true, width: w, height: h, views: out };
}

// Every entry point reports errors in its result instead of throwing across page.evaluate.
function guarded(fn) {
  return async (...args) => {
    try {
      return Object.assign({ errors: [] }, await fn(...args));
    } catch (e) {
      return { ok: false, errors: [String(e && e.stack || e)] };
    }
  };
}

window.lodbakeSetup = guarded(setup);
window.lodbakeFrame = guarded(frameOn);
window.lodbakeRender = guarded(renderViews);
window.lodbakeThreeReady = true;
