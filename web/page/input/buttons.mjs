// grove's four controller buttons, as every input source hands them to the page: the gamepad's
// state mapped to them (ButtonMapper: Bumper's alternative on a controller without a squeeze),
// read at the simulation's tick and turned into edges (never from `select` events, which
// emulators and browsers fire at different moments), and the touchpad's axes from a thumbstick
// or a touchpad (docs/headset.md, "Devices and their mappings").

/** grove's buttons, in the order a snapshot's `controller.buttons` lists them. */
export const BUTTONS = ['trigger', 'bumper', 'touchpad', 'menu'];

/** How long a touchpad press must be held to be Menu on a controller without a squeeze, ms. */
export const LONG_PRESS_MS = 500;

const pressed = (gamepad, i) => Boolean(gamepad?.buttons?.[i]?.pressed);

/**
 * Whether a controller has no squeeze button: Magic Leap 2 in Wolvic reports the `magicleap-one`
 * profile (trigger, touchpad, and a menu button the browser keeps for itself), and a gamepad
 * with fewer than two buttons has none either.
 */
export function lacksSqueeze(profiles, gamepad) {
  return (profiles ?? []).includes('magicleap-one') || (gamepad?.buttons?.length ?? 0) < 2;
}

/**
 * Maps an XR standard gamepad to grove's buttons. Trigger is button 0, Bumper the squeeze
 * (button 1), Touchpad the touchpad or thumbstick press (buttons 2 and 3), Menu the A/X or B/Y
 * button (4 and 5). On a controller without a squeeze (`lacksSqueeze`), the touchpad press is
 * both: a click shorter than LONG_PRESS_MS is Bumper (pressed when the click ends and released
 * at the next tick), a press held that long is Menu (released with the press).
 */
export class ButtonMapper {
  constructor({ noSqueeze = false } = {}) {
    this.noSqueeze = noSqueeze;
    this.padSince = null; // when the touchpad went down (no-squeeze mapping), ms
    this.bumperPulse = false;
    this.menuHeld = false;
  }

  /** The four buttons' states now (`tMs`: the tick's time). */
  read(gamepad, tMs) {
    const trigger = pressed(gamepad, 0);
    const pad = pressed(gamepad, 2) || pressed(gamepad, 3);
    if (!this.noSqueeze) {
      return { trigger, bumper: pressed(gamepad, 1), touchpad: pad, menu: pressed(gamepad, 4) || pressed(gamepad, 5) };
    }
    let bumper = false;
    if (this.bumperPulse) {
      this.bumperPulse = false; // the click's Bumper is released one tick after it went down
    }
    if (pad) {
      if (this.padSince === null) this.padSince = tMs;
      if (tMs - this.padSince >= LONG_PRESS_MS) this.menuHeld = true;
    } else if (this.padSince !== null) {
      if (!this.menuHeld) {
        bumper = true;
        this.bumperPulse = true;
      }
      this.padSince = null;
      this.menuHeld = false;
    }
    return { trigger, bumper, touchpad: false, menu: this.menuHeld };
  }
}

/** The buttons that changed from `before` to `now`, as grove's events, in BUTTONS order. */
export function edges(before, now) {
  const out = [];
  for (const b of BUTTONS) {
    if (Boolean(before[b]) !== Boolean(now[b])) out.push({ kind: now[b] ? 'button_down' : 'button_up', button: b });
  }
  return out;
}

/** The states a snapshot's `controller.buttons` array holds, by name. */
export function statesOf(buttons) {
  return Object.fromEntries(BUTTONS.map((b, i) => [b, Boolean(buttons?.[i])]));
}

const DEADZONE = 0.15;
const STEPS = 32;

/**
 * The touchpad's axes as grove takes them (each in [-1, 1], +Y to the front, +X to the right)
 * from a gamepad's thumbstick (axes 2 and 3) or touchpad (0 and 1), whichever is off centre:
 * quantized to 1/32 with a dead zone, so that a resting thumb does not make an event every tick.
 */
export function touchpadAxes(gamepad) {
  const a = gamepad?.axes ?? [];
  const pick = Math.hypot(a[2] ?? 0, a[3] ?? 0) >= Math.hypot(a[0] ?? 0, a[1] ?? 0) ? [a[2] ?? 0, a[3] ?? 0] : [a[0] ?? 0, a[1] ?? 0];
  const q = (v) => {
    const c = Math.max(-1, Math.min(1, v));
    return Math.abs(c) < DEADZONE ? 0 : Math.round(c * STEPS) / STEPS;
  };
  // The gamepad's +Y is towards the user (down on the stick); grove's +Y is to the front.
  return [q(pick[0]), q(-pick[1]) || 0];
}
