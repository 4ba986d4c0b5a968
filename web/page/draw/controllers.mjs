// The controller itself, drawn from the WebXR Input Profiles: the profile that matches the input
// source (@webxr-input-profiles/motion-controllers, from the profiles the page ships under
// `profiles/`), its glTF model, and its buttons and thumbstick moved by the gamepad's state
// through the profile's visual responses. An input source without a shipped profile gets a plain
// stick. Drawn at the grip pose, in the session's reference space. A feature of the view
// (view/features.mjs), drawn in an immersive session's frames.

import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { Constants, MotionController, fetchProfile } from '@webxr-input-profiles/motion-controllers';
import { XrController } from '../input/xr.mjs';

const PROFILES = new URL('profiles', document.baseURI).href.replace(/\/?$/, '');

function stick() {
  const m = new THREE.Mesh(new THREE.CylinderGeometry(0.015, 0.02, 0.14, 10), new THREE.MeshStandardMaterial({ color: 0x303438 }));
  m.rotation.x = Math.PI / 2;
  const g = new THREE.Group();
  g.add(m);
  return g;
}

/** One input source's drawn controller. */
class Drawn {
  constructor(scene, source, loader) {
    this.source = source;
    this.group = new THREE.Group();
    this.group.name = `controller:${source.handedness}`;
    scene.add(this.group);
    this.motion = null;
    this.nodes = null;
    this.profile = '';
    fetchProfile(source, PROFILES)
      .then(async ({ profile, assetPath }) => {
        this.motion = new MotionController(source, profile, assetPath);
        this.profile = profile.profileId;
        const gltf = await loader.loadAsync(assetPath);
        this.group.add(gltf.scene);
        this.nodes = this.#findNodes(gltf.scene);
      })
      .catch(() => {
        this.profile = 'none';
        this.group.add(stick());
      });
  }

  #findNodes(root) {
    const nodes = [];
    for (const component of Object.values(this.motion.components)) {
      for (const response of Object.values(component.visualResponses)) {
        const value = root.getObjectByName(response.valueNodeName);
        if (!value) continue;
        const entry = { response, value };
        if (response.valueNodeProperty === Constants.VisualResponseProperty.TRANSFORM) {
          entry.min = root.getObjectByName(response.minNodeName);
          entry.max = root.getObjectByName(response.maxNodeName);
          if (!entry.min || !entry.max) continue;
        }
        nodes.push(entry);
      }
    }
    return nodes;
  }

  update(frame, space) {
    const pose = frame.getPose(this.source.gripSpace ?? this.source.targetRaySpace, space);
    this.group.visible = Boolean(pose);
    if (!pose) return;
    const { position: p, orientation: q } = pose.transform;
    this.group.position.set(p.x, p.y, p.z);
    this.group.quaternion.set(q.x, q.y, q.z, q.w);
    if (!this.motion || !this.nodes) return;
    this.motion.updateFromGamepad();
    for (const { response, value, min, max } of this.nodes) {
      if (response.valueNodeProperty === Constants.VisualResponseProperty.VISIBILITY) {
        value.visible = response.value;
      } else if (min && max) {
        value.quaternion.slerpQuaternions(min.quaternion, max.quaternion, response.value);
        value.position.lerpVectors(min.position, max.position, response.value);
      }
    }
  }

  dispose(scene) {
    scene.remove(this.group);
  }
}

/** Every controller of an XR session. */
export class Controllers {
  constructor(scene) {
    this.scene = scene;
    this.loader = new GLTFLoader();
    this.drawn = new Map();
  }

  /** Draws every controller of the XR frame (`s.xr`: { frame, space }), if there is one. */
  update(s) {
    if (s.xr) this.#sync(s.xr.frame, s.xr.space);
  }

  #sync(frame, space) {
    const sources = new Set(frame.session.inputSources);
    for (const source of sources) {
      if (!XrController.accepts(source)) continue;
      if (!this.drawn.has(source)) this.drawn.set(source, new Drawn(this.scene, source, this.loader));
      this.drawn.get(source).update(frame, space);
    }
    for (const [source, d] of this.drawn) {
      if (!sources.has(source)) {
        d.dispose(this.scene);
        this.drawn.delete(source);
      }
    }
  }

  /** The profile each drawn controller uses ('' while loading, 'none' without one). */
  profiles() {
    return [...this.drawn.values()].map((d) => d.profile);
  }
}
