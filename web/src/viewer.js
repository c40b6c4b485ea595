// The three.js scene: one surface with per-vertex colours, orbit controls on the desktop, and
// the same scene in WebXR (immersive-vr) where the browser has it.
import * as THREE from 'three';
import { OrbitControls } from 'three/examples/jsm/controls/OrbitControls.js';
import { VRButton } from 'three/examples/jsm/webxr/VRButton.js';

// In VR the surface is scaled to this radius (metres) and floats at a standing user's chest
// height, an arm's length in front: big enough to read the colours, small enough to walk round.
const VR_RADIUS = 0.4;
const VR_CENTRE = new THREE.Vector3(0, 1.3, -1.0);

export class Viewer {
  constructor(container) {
    this.renderer = new THREE.WebGLRenderer({ antialias: true });
    this.renderer.setPixelRatio(window.devicePixelRatio);
    this.renderer.xr.enabled = true;
    container.appendChild(this.renderer.domElement);

    this.scene = new THREE.Scene();
    this.scene.background = new THREE.Color(0x202428);
    this.camera = new THREE.PerspectiveCamera(40, 1, 0.01, 100);
    this.camera.position.set(0, 0, 3.2);
    // A head light, so the side facing the viewer shows the colour map's colours unchanged
    // (ambient + direct = 1; three.js's Lambert divides both by pi) and tilted parts get
    // darker, which shows the shape.
    this.scene.add(new THREE.AmbientLight(0xffffff, 0.35 * Math.PI));
    const headLight = new THREE.DirectionalLight(0xffffff, 0.65 * Math.PI);
    headLight.position.set(0, 0, 1);
    headLight.target.position.set(0, 0, -1);
    this.camera.add(headLight, headLight.target);
    this.scene.add(this.camera);

    this.controls = new OrbitControls(this.camera, this.renderer.domElement);
    this.controls.enableDamping = true;

    // The surface in a unit frame (centred, radius 1), the same for every level of a surface.
    this.model = new THREE.Group();
    this.scene.add(this.model);
    this.material = new THREE.MeshLambertMaterial({ vertexColors: true, side: THREE.DoubleSide });
    this.mesh = null;
    // The triangles' edges, drawn over the surface on demand (to see what simplification did).
    this.edges = new THREE.Mesh(undefined, new THREE.MeshBasicMaterial({
      color: 0x000000, wireframe: true, transparent: true, opacity: 0.35 }));
    this.edges.visible = false;
    this.frame = null; // { centre, radius } of the surface being shown

    this.renderer.xr.addEventListener('sessionstart', () => this.placeModel(true));
    this.renderer.xr.addEventListener('sessionend', () => this.placeModel(false));
    new ResizeObserver(() => this.resize(container)).observe(container);
    this.resize(container);
    this.renderer.setAnimationLoop(() => {
      if (!this.renderer.xr.isPresenting) this.controls.update();
      this.renderer.render(this.scene, this.camera);
    });
  }

  // Adds the "Enter VR" button when the browser can show immersive-vr.
  async offerVR(parent) {
    if (!navigator.xr?.isSessionSupported) return false;
    let supported = false;
    try {
      supported = await navigator.xr.isSessionSupported('immersive-vr');
    } catch {
      supported = false;
    }
    if (!supported) return false;
    const button = VRButton.createButton(this.renderer);
    button.dataset.testid = 'enter-vr';
    // VRButton positions itself over the canvas; keep that.
    parent.appendChild(button);
    return true;
  }

  resize(container) {
    const w = Math.max(1, container.clientWidth);
    const h = Math.max(1, container.clientHeight);
    this.renderer.setSize(w, h, false);
    this.renderer.domElement.style.width = '100%';
    this.renderer.domElement.style.height = '100%';
    this.camera.aspect = w / h;
    this.camera.updateProjectionMatrix();
  }

  // Shows vertices `positions` (3 floats each, the first vertexCount used), triangles `slots`
  // (slotCount triples) and per-vertex sRGB `colours`. `surfaceKey` names the surface: a new
  // one is framed afresh, a new level of the same one keeps the user's view.
  show({ surfaceKey, positions, vertexCount, slots, slotCount, colours }) {
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute(
      'position', new THREE.BufferAttribute(positions.slice(0, 3 * vertexCount), 3));
    geometry.setAttribute('color', new THREE.BufferAttribute(colours, 3));
    geometry.setIndex(new THREE.BufferAttribute(slots.slice(0, 3 * slotCount), 1));
    geometry.computeVertexNormals();
    geometry.computeBoundingSphere();
    if (this.mesh) {
      this.mesh.geometry.dispose();
      this.mesh.geometry = geometry;
    } else {
      this.mesh = new THREE.Mesh(geometry, this.material);
      this.model.add(this.mesh, this.edges);
    }
    this.edges.geometry = geometry;
    if (this.frameKey !== surfaceKey) {
      this.frameKey = surfaceKey;
      const s = geometry.boundingSphere;
      this.frame = { centre: s.center.clone(), radius: s.radius > 0 ? s.radius : 1 };
      this.placeModel(this.renderer.xr.isPresenting);
      this.lookAtFront();
    }
  }

  // New colours for the vertices shown (same count as the last show()).
  recolour(colours) {
    if (!this.mesh) return;
    this.mesh.geometry.setAttribute('color', new THREE.BufferAttribute(colours, 3));
  }

  showEdges(on) {
    this.edges.visible = on;
  }

  placeModel(inVR) {
    if (!this.frame) return;
    const scale = (inVR ? VR_RADIUS : 1) / this.frame.radius;
    this.model.scale.setScalar(scale);
    const at = inVR ? VR_CENTRE : new THREE.Vector3();
    this.model.position.copy(at).addScaledVector(this.frame.centre, -scale);
  }

  // Looks at the surface along its smallest extent (a cutting plane face on).
  lookAtFront() {
    const box = new THREE.Box3().setFromObject(this.model);
    const size = box.getSize(new THREE.Vector3());
    const axis = new THREE.Vector3();
    if (size.x <= size.y && size.x <= size.z) axis.set(1, 0, 0);
    else if (size.y <= size.z) axis.set(0, 1, 0);
    else axis.set(0, 0, 1);
    const distance = 1 / Math.sin(THREE.MathUtils.degToRad(this.camera.fov / 2)) * 1.05;
    this.controls.target.set(0, 0, 0);
    this.camera.position.copy(axis.multiplyScalar(distance));
    this.camera.up.set(0, axis.y === 0 ? 1 : 0, axis.y === 0 ? 0 : -1);
    this.camera.lookAt(0, 0, 0);
    this.controls.update();
  }
}
