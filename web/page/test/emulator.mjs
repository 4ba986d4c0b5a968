// The WebXR device the browser tests emulate (never part of the page a headset gets): IWER's
// Meta Quest 3 with Touch Plus controllers, installed over Chromium's own navigator.xr, and for
// AR a room from @iwer/sem (a small office, with its planes and hit test). Bundled by harness.mjs
// into one script that Playwright adds before the page's own scripts; `window.__groveXR`
// ({ room: true|false, depth: true|false, light }) chooses the room, whether the headset offers
// depth sensing, and a light estimate.

import { XRDevice, XRFrame, XRSession, metaQuest3 } from 'iwer';
import { SyntheticEnvironmentModule } from '@iwer/sem';
import office from '@iwer/sem/captures/office_small.json';

const config = window.__groveXR ?? { room: true };
// `depth: false`: a headset without depth sensing (IWER's Quest 3 offers it, from the room's meshes).
// `light: { sh, direction, intensity }`: a test double of WebXR light estimation (IWER has none):
// the session grants `light-estimation`, its light probe gives this estimate every frame.
const features = metaQuest3.supportedFeatures.filter((f) => f !== 'depth-sensing' || config.depth !== false);
const headset = { ...metaQuest3, supportedFeatures: config.light ? [...features, 'light-estimation'] : features };
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
