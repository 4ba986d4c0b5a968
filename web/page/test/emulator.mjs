// The WebXR device the browser tests emulate (never part of the page a headset gets): IWER's
// Meta Quest 3 with Touch Plus controllers (or its hands), installed over Chromium's own
// navigator.xr, and for AR a room from @iwer/sem (a small office, with its planes and hit test).
// Bundled by harness.mjs into one script that Playwright adds before the page's own scripts;
// `window.__groveXR` ({ room, device }) chooses the room and the device: `quest` (the default),
// `quest2` (IWER's Quest 2: Touch controllers, profile oculus-touch-v3, no depth sensing),
// `pico4` (a double: its controllers as the pico-4 profile over the Touch layout, no hit test or
// depth), `magicleap` (a double of Magic Leap 2's controller in Wolvic: magicleap-one, no
// squeeze), `phone` (an Android phone: immersive-ar only, 'screen-space', no controllers) or
// `visionpro` (immersive-vr only, no controllers); `depth: false` a headset without depth sensing, `light` a
// light estimate (below).
//
// IWER emulates neither `screen` nor `transient-pointer` input, so for those devices this file
// adds test doubles of XRInputSource (`window.xrDouble`, input/sources.mjs meets them as it would
// a browser's): a screen touch whose target ray leaves the camera towards a point, with the
// browser's hit test for transient input (the floor under the finger); a pinch whose target ray
// is the gaze when it began and whose grip space is the hand; and for the phone the DOM
// overlay shown above the XR canvas, as a phone's browser shows it.

import * as THREE from 'three';
import {
  GlobalSpace,
  P_DEVICE,
  P_SPACE,
  XRDevice,
  XRFrame,
  XRInputSource,
  XRSession,
  XRSpace,
  metaQuest2,
  metaQuest3,
  oculusTouchV3,
} from 'iwer';
import { SyntheticEnvironmentModule } from '@iwer/sem';
import office from '@iwer/sem/captures/office_small.json';

const config = window.__groveXR ?? { room: true };
const kind = config.device ?? 'quest';
// Magic Leap 2's controller as Wolvic reports it: the magicleap-one profile, a trigger and a
// touchpad, no squeeze (the menu button is the browser's own).
const ML_GAMEPAD = {
  mapping: 'xr-standard',
  buttons: [{ id: 'trigger', type: 'analog', eventTrigger: 'select' }, null, { id: 'touchpad', type: 'binary' }],
  axes: [
    { id: 'touchpad', type: 'x-axis' },
    { id: 'touchpad', type: 'y-axis' },
  ],
};
const ML_HAND = { gamepad: ML_GAMEPAD, gripOffsetMatrix: new THREE.Matrix4().elements, numHapticActuators: 1 };
const magicLeapOne = {
  profileId: 'magicleap-one',
  fallbackProfileIds: ['generic-trigger-touchpad'],
  layout: { left: ML_HAND, right: ML_HAND },
};
// Pico 4's controllers: the Touch layout (trigger, squeeze, thumbstick, A/B and X/Y) under the
// pico-4 profile.
const pico4 = { ...oculusTouchV3, profileId: 'pico-4', fallbackProfileIds: ['generic-trigger-squeeze-thumbstick'] };
const DEVICES = {
  quest: metaQuest3,
  quest2: metaQuest2,
  phone: {
    ...metaQuest3,
    name: 'Android phone (emulated)',
    controllerConfig: undefined,
    supportedSessionModes: ['inline', 'immersive-ar'],
    supportedFeatures: ['viewer', 'local', 'local-floor', 'anchors', 'plane-detection', 'hit-test', 'dom-overlay'],
    interactionMode: 'screen-space',
  },
  pico4: {
    ...metaQuest3,
    name: 'Pico 4 (emulated)',
    controllerConfig: pico4,
    supportedFeatures: metaQuest3.supportedFeatures.filter((f) => !['depth-sensing', 'hit-test'].includes(f)),
  },
  magicleap: {
    ...metaQuest3,
    name: 'Magic Leap 2 in Wolvic (emulated)',
    controllerConfig: magicLeapOne,
    supportedFeatures: metaQuest3.supportedFeatures.filter((f) => !['depth-sensing', 'hand-tracking'].includes(f)),
  },
  visionpro: {
    ...metaQuest3,
    name: 'Apple Vision Pro (emulated)',
    controllerConfig: undefined,
    supportedSessionModes: ['inline', 'immersive-vr'],
    supportedFeatures: ['viewer', 'local', 'local-floor', 'hand-tracking'],
  },
};
// `depth: false`: a headset without depth sensing (IWER's Quest 3 offers it, from the room's meshes).
// `light: { sh, direction, intensity }`: a test double of WebXR light estimation (IWER has none):
// the session grants `light-estimation`, its light probe gives this estimate every frame.
const features = DEVICES[kind].supportedFeatures.filter((f) => f !== 'depth-sensing' || config.depth !== false);
const headset = { ...DEVICES[kind], supportedFeatures: config.light ? [...features, 'light-estimation'] : features };
if (config.light) {
  const { sh, direction, intensity } = config.light;
  XRSession.prototype.requestLightProbe = () => Promise.resolve(new EventTarget());
  XRFrame.prototype.getLightEstimate = () => ({
    sphericalHarmonicsCoefficients: Float32Array.from(sh),
    primaryLightDirection: { x: direction[0], y: direction[1], z: direction[2], w: 0 },
    primaryLightIntensity: { x: intensity[0], y: intensity[1], z: intensity[2], w: 1 },
  });
}
const device = new XRDevice(headset, { stereoEnabled: false });
device.installRuntime({ forceInstall: true });
if (config.room) {
  device.installSEM(SyntheticEnvironmentModule);
  device.sem.loadEnvironment(office);
}
window.xrDevice = device;

// The doubles: extra XR input sources beside IWER's own (none on the phone and the Vision Pro).
const extra = [];
const own = Object.getOwnPropertyDescriptor(XRDevice.prototype, 'inputSources').get;
Object.defineProperty(device, 'inputSources', { get: () => [...own.call(device), ...extra] });
const global = device[P_DEVICE].globalSpace ?? new GlobalSpace();

function place(space, position, quaternion) {
  const m = new THREE.Matrix4().compose(position, quaternion, new THREE.Vector3(1, 1, 1));
  space[P_SPACE].offsetMatrix.set(m.elements);
}

function spaceAt(position, quaternion = new THREE.Quaternion()) {
  const s = new XRSpace(global);
  place(s, position, quaternion);
  return s;
}

/** The orientation whose -Z points from `from` to `to` (THREE.Vector3s). */
function towards(from, to) {
  const m = new THREE.Matrix4().lookAt(from, to, new THREE.Vector3(0, 1, 0));
  return new THREE.Quaternion().setFromRotationMatrix(m);
}

const session = (p) => {
  const s = window.grove.toSession(p);
  return new THREE.Vector3(s.x, s.y, s.z);
};
const head = () => new THREE.Vector3(device.position.x, device.position.y, device.position.z);

/** The hit test for transient input: where each screen touch's ray meets the floor the page found. */
XRSession.prototype.requestHitTestSourceForTransientInput = async function (options) {
  return { profile: options?.profile, cancel() {} };
};
XRFrame.prototype.getHitTestResultsForTransientInput = function () {
  const floorY = window.grove?.floor?.y ?? 0;
  return extra
    .filter((s) => s.targetRayMode === 'screen')
    .map((s) => {
      const m = new THREE.Matrix4().fromArray(s.targetRaySpace[P_SPACE].offsetMatrix);
      const o = new THREE.Vector3().setFromMatrixPosition(m);
      const d = new THREE.Vector3(0, 0, -1).applyQuaternion(new THREE.Quaternion().setFromRotationMatrix(m));
      const results = [];
      if (d.y < -1e-6) {
        const p = o.clone().addScaledVector(d, (floorY - o.y) / d.y);
        results.push({
          getPose: () => ({
            transform: { position: { x: p.x, y: p.y, z: p.z }, orientation: { x: 0, y: 0, z: 0, w: 1 } },
          }),
        });
      }
      return { inputSource: s, results };
    });
};

window.xrDouble = {
  /** A finger comes down on the screen where the camera sees `simPoint` ([x, y, z], the simulation's frame). */
  touch(simPoint) {
    const from = head();
    const s = new XRInputSource(
      'none',
      'screen',
      ['generic-touchscreen'],
      spaceAt(from, towards(from, session(simPoint))),
    );
    extra.push(s);
    return extra.length - 1;
  },
  /** The finger moves to where the camera sees `simPoint`. */
  move(simPoint) {
    const s = extra.find((x) => x.targetRayMode === 'screen');
    const from = head();
    place(s.targetRaySpace, from, towards(from, session(simPoint)));
  },
  /** A hand pinches (`hand`: 'right' or 'left') while the eyes look at `simPoint`; the hand (its grip) at `grip` ([x, y, z], simulation's frame). */
  pinch(simPoint, hand = 'right', grip = null) {
    const from = head();
    const g = grip ? session(grip) : from.clone().add(new THREE.Vector3(hand === 'left' ? -0.2 : 0.2, -0.4, -0.3));
    const s = new XRInputSource(
      hand,
      'transient-pointer',
      ['generic-button'],
      spaceAt(from, towards(from, session(simPoint))),
      undefined,
      spaceAt(g),
    );
    extra.push(s);
  },
  /** The pinching hand (`hand`) moves its grip to `grip` ([x, y, z], the simulation's frame); the gaze ray stays. */
  moveGrip(grip, hand = 'right') {
    const s = extra.find((x) => x.targetRayMode === 'transient-pointer' && x.handedness === hand);
    place(s.gripSpace, session(grip), new THREE.Quaternion());
  },
  /** Where the pinching hand's grip is, [x, y, z] in the session's space. */
  grip(hand = 'right') {
    const s = extra.find((x) => x.targetRayMode === 'transient-pointer' && x.handedness === hand);
    const p = new THREE.Vector3().setFromMatrixPosition(
      new THREE.Matrix4().fromArray(s.gripSpace[P_SPACE].offsetMatrix),
    );
    return [p.x, p.y, p.z];
  },
  /** The finger lifts, or the pinch of `hand` ends. */
  lift(hand) {
    const i = extra.findIndex((x) => (hand ? x.handedness === hand : true));
    if (i >= 0) extra.splice(i, 1);
  },
  /** How many doubles there are now. */
  count: () => extra.length,
};

// A phone's browser shows the DOM overlay's root above the XR content.
if (kind === 'phone') {
  const lift = () => {
    const overlay = document.getElementById('overlay');
    const box = device[P_DEVICE].canvasContainer;
    if (overlay && box.isConnected && overlay.parentElement !== box) {
      overlay.style.zIndex = '1000';
      box.appendChild(overlay);
    }
    requestAnimationFrame(lift);
  };
  requestAnimationFrame(lift);
}

// The scripted participant's hand (participant.mjs): the right controller, or with hand tracking
// (`xrDevice.primaryInputMode = 'hand'`) the right hand, whose pinch is the trigger; the menu's
// B button is then the left hand's pinch (held), Bumper's squeeze its short pinch.
window.xrParticipant = {
  pointer: () => (device.primaryInputMode === 'hand' ? device.hands.right : device.controllers.right),
  press(button, value) {
    if (device.primaryInputMode !== 'hand') return device.controllers.right.updateButtonValue(button, value);
    const hand = button === 'trigger' ? device.hands.right : device.hands.left;
    hand.updatePinchValue(value);
  },
};
