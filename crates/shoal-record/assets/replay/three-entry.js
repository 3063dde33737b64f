// The three.js exports the viewer files (replay-data.js, replay-scene.js, replay.js) use (THREE.<name>); scripts/vendor-three.sh bundles exactly
// these into three-<version>.min.js (esbuild IIFE, global THREE, tree-shaken, minified).
// Add a name here when replay.js starts using it, then rerun the script; the unit test
// `replay::html::tests::the_bundle_exports_what_the_viewer_uses` checks the two agree.
export {
  REVISION,
  WebGLRenderer,
  Scene,
  PerspectiveCamera,
  Color,
  Group,
  Matrix4,
  Vector2,
  Vector3,
  Raycaster,
  BufferGeometry,
  BufferAttribute,
  BoxGeometry,
  SphereGeometry,
  CylinderGeometry,
  CapsuleGeometry,
  PlaneGeometry,
  EdgesGeometry,
  Mesh,
  InstancedMesh,
  LineSegments,
  MeshStandardMaterial,
  MeshBasicMaterial,
  LineBasicMaterial,
  HemisphereLight,
  DirectionalLight,
  DynamicDrawUsage,
  DoubleSide,
  BackSide,
} from 'three';
export { OrbitControls } from 'three/addons/controls/OrbitControls.js';
