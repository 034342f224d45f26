// Fixed physically based render setup for comparing glTF files as users see them in three.js:
// PMREM of RoomEnvironment as scene.environment, one directional light, Neutral tone mapping,
// sRGB output, transparent background, a perspective camera framing the bounding sphere of a
// reference file's vertices from `views` azimuths (every 360/views degrees) at one elevation.
//
// API for the driver (three_run.js), once window.lodbakeThreeReady is true:
//   await lodbakeSetup({size})             renderer and lights (size: square image side, pixels)
//   await lodbakeFrame(url)                frames the cameras on this file's scene
//   await lodbakeRender(url, node, views, elevationDeg)
//       renders the file's default scene, or only node `node` (an index, with its children)
//       when node >= 0; returns {ok, errors, width, height, views: [base64 RGBA, rows top-down,
//       RGB premultiplied by alpha = composited over black]}.
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

async function loadObject(url, node) {
  const gltf = await loader.loadAsync(url);
  let object = gltf.scene || (gltf.scenes && gltf.scenes[0]);
  if (node >= 0) {
    const count = (gltf.parser.json.nodes || []).length;
    if (node >= count) throw new Error('node ' + node + ' out of range (' + count + ' nodes)');
    object = await gltf.parser.getDependency('node', node);
    object.removeFromParent();
  }
  if (!object) throw new Error('no scene in ' + url);
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

function toBase64(bytes) {
  let s = '';
  const chunk = 0x8000;
  for (let i = 0; i < bytes.length; i += chunk) s += String.fromCharCode.apply(null, bytes.subarray(i, i + chunk));
  return btoa(s);
}

async function renderViews(url, node, views, elevationDeg) {
  if (!frame) throw new Error('lodbakeFrame was not called');
  const object = await loadObject(url, node);
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
  const out = [];
  for (let v = 0; v < views; ++v) {
    const azimuth = 2 * Math.PI * v / views;
    camera.position.set(frame.center.x + distance * Math.cos(elevation) * Math.sin(azimuth),
                        frame.center.y + distance * Math.sin(elevation),
                        frame.center.z + distance * Math.cos(elevation) * Math.cos(azimuth));
    camera.lookAt(frame.center);
    camera.updateMatrixWorld(true);
    renderer.render(scene, camera);
    gl.readPixels(0, 0, w, h, gl.RGBA, gl.UNSIGNED_BYTE, pixels);
    for (let y = 0; y < h; ++y) flipped.set(pixels.subarray((h - 1 - y) * w * 4, (h - y) * w * 4), y * w * 4);
    out.push(toBase64(flipped));
  }
  scene.remove(object);
  disposeObject(object);
  return { ok: true, width: w, height: h, views: out };
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
