// The WebXR device the browser tests emulate (never part of the page a headset gets): IWER's
// Meta Quest 3 with Touch Plus controllers, installed over Chromium's own navigator.xr, and for
// AR a room from @iwer/sem (a small office, with its planes and hit test). Bundled by harness.mjs
// into one script that Playwright adds before the page's own scripts; `window.__groveXR`
// ({ room: true|false }) chooses the room.

import { XRDevice, metaQuest3 } from 'iwer';
import { SyntheticEnvironmentModule } from '@iwer/sem';
import office from '@iwer/sem/captures/office_small.json';

const config = window.__groveXR ?? { room: true };
const device = new XRDevice(metaQuest3, { stereoEnabled: false });
device.installRuntime({ forceInstall: true });
if (config.room) {
  device.installSEM(SyntheticEnvironmentModule);
  device.sem.loadEnvironment(office);
}
window.xrDevice = device;
