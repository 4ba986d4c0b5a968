// An XR controller as grove's input source: a `tracked-pointer` with a gamepad (Quest's Touch,
// Pico's, Magic Leap 2's). Its target ray is the controller's pose; its gamepad's buttons are
// grove's through ButtonMapper (Bumper's alternative on a controller without a squeeze); its
// thumbstick or touchpad is the touchpad's axes (docs/headset.md, "Devices and their mappings").
//
// Every input source has this shape (input/sources.mjs chooses one per XR input source):
//   static accepts(xrInputSource)  whether this kind of source takes it;
//   poll(frame)    this frame's { pose, buttons, axes }: pose in the simulation's frame
//                  (input/pose.mjs) or null, grove's buttons by name, the touchpad's [x, y];
//   controls(mode) the rows [control, what it does] the page lists for a task's mode;
//   device()       what the recording's header says of it: { profile, target_ray_mode, mapping };
//   refuses(mode)  why a task's mode cannot be done with it (the page refuses at the start), or null;
//   noSqueeze      whether Bumper has its alternative (the task panel says so).

import { ButtonMapper, LONG_PRESS_MS, lacksSqueeze, touchpadAxes } from './buttons.mjs';
import { deviceOf } from './device.mjs';
import { simPose } from './pose.mjs';

/** A controller's rows [control, what it does] for a task's mode ('ray-casting' or 'manual'). */
export function controllerControls(mode, noSqueeze) {
  const rows = [['Trigger', mode === 'manual' ? 'grab and drag a tree or a handle; choose in the menu' : 'plant on the ground, select a tree; choose in the menu']];
  if (noSqueeze) {
    rows.push(['Touchpad click', 'remove the tree under the ray (this controller has no squeeze button: a click is Bumper)']);
    rows.push([`Touchpad held ${LONG_PRESS_MS / 1000} s`, 'open the model menu']);
    rows.push(['Touchpad (touch)', 'move the selected tree along the ray and turn it']);
  } else {
    rows.push(['Squeeze (grip)', 'remove the tree under the ray (Bumper)']);
    rows.push(['A / B (X / Y)', 'open the model menu']);
    rows.push(['Thumbstick', 'move the selected tree along the ray and turn it; press: Touchpad']);
  }
  return rows;
}

export class XrController {
  static accepts(source) {
    return source.targetRayMode === 'tracked-pointer' && Boolean(source.gamepad) && !source.hand;
  }

  /** `ctx`: { space (the session's reference space), offset() (room.mjs's simOffset, or null), now() (ms) }. */
  constructor(source, ctx) {
    this.source = source;
    this.ctx = ctx;
    this.noSqueeze = lacksSqueeze(source.profiles, source.gamepad);
    this.mapper = new ButtonMapper({ noSqueeze: this.noSqueeze });
  }

  get handedness() {
    return this.source.handedness;
  }

  poll(frame) {
    const { gamepad, targetRaySpace } = this.source;
    const pose = frame.getPose(targetRaySpace, this.ctx.space);
    return { pose: simPose(pose?.transform, this.ctx.offset()), buttons: this.mapper.read(gamepad, this.ctx.now()), axes: touchpadAxes(gamepad) };
  }

  controls(mode) {
    return controllerControls(mode, this.noSqueeze);
  }

  /** What the recording's header says of this device. */
  device() {
    return deviceOf(this.source, this.noSqueeze ? 'controller-no-squeeze' : 'controller');
  }

  /** Why a task's mode cannot be done with this device, or null: a controller does both. */
  refuses() {
    return null;
  }
}
