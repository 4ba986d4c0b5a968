// The fixed-step clock of the page's frame loop: the time between frames in, whole simulation
// steps out (as the desktop's FixedStep, src/desktop/session.rs). A stall longer than `maxSteps`
// steps is dropped rather than caught up, so a slow frame never makes the next one slower.

export class FixedStep {
  /** `dt`: the scene's step, seconds; `maxSteps`: the most steps one frame may run. */
  constructor(dt, maxSteps = 8) {
    this.dt = dt;
    this.maxSteps = maxSteps;
    this.accumulator = 0;
  }

  /** Adds `elapsed` seconds and returns how many steps to run now. */
  advance(elapsed) {
    if (!(Number.isFinite(elapsed) && elapsed > 0 && this.dt > 0)) return 0;
    this.accumulator += elapsed;
    const n = Math.floor(this.accumulator / this.dt);
    const steps = Math.min(n, this.maxSteps);
    this.accumulator -= steps * this.dt;
    if (steps === this.maxSteps) this.accumulator = Math.min(this.accumulator, this.dt);
    return steps;
  }
}
