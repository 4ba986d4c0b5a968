// The drawn features of the page's view, one module each (draw/), made once when the view is and
// updated every frame in this order. A feature is an object with `update(s)`, where `s` is the
// frame's state that the flow hands the view (flow/frame.mjs):
//
//   s.state   the page's state (flow/flow.mjs)
//   s.world   the world shown: { ar, ground, snapshot } (flow/task.mjs's worldOf), or null in AR
//             before a run (the room is all there is)
//   s.snap    the run's snapshot (systems/src/snapshot.rs), or null
//   s.live    the same while the run is shown with its ray, box, targets and menu (not on a
//             step's panel), else null
//   s.xr      { frame, space }: the XR frame and the session's reference space, or null
//   s.ray     the pointer's ray, [origin, direction] in the simulation's frame, or null
//   s.eye     where labels turn to, {x, y, z} in the simulation's frame, or null
//   s.hud     the task panel's { lines, at, eye }, or null (hidden)
//   s.panel   whether a protocol's panel may show
//
// Everything the flow draws is in the simulation's frame (`view.simRoot`), placed in the
// session's reference space by the offset (room.mjs); `view.scene` is the session's space.
// A new feature (depth occlusion …) is one module in draw/ and one line here; a new field of `s`
// is one line in flow/frame.mjs. A feature may also have `beforeSession(session)`, called as an
// immersive session is presented (view/view.mjs). The world's features are drawn as grove's
// renderer draws them (docs/headset.md, "How the page draws trees"); while a light estimate lights
// AR, `scene.environment` is draw/xrlight.mjs's, given back after.

import { Controllers } from '../draw/controllers.mjs';
import { Ground } from '../draw/ground.mjs';
import { Forest } from '../draw/forest.mjs';
import { Hud } from '../draw/hud.mjs';
import { LeafDetail } from '../draw/leaves.mjs';
import { Light } from '../draw/light.mjs';
import { Menu } from '../draw/menu.mjs';
import { Occlusion } from '../draw/occlusion.mjs';
import { Overlay } from '../draw/overlay.mjs';
import { Panel } from '../draw/panel.mjs';
import { SkyFeature } from '../draw/sky.mjs';
import { Wind } from '../draw/wind.mjs';
import { World } from '../draw/world.mjs';
import { XrLight } from '../draw/xrlight.mjs';

/** name -> make(view): the view's features (`view.features.NAME`). */
export const FEATURES = {
  overlay: (v) => new Overlay(v.simRoot),
  menu: (v) => new Menu(v.simRoot),
  hud: (v) => new Hud(v.simRoot),
  panel: (v) => new Panel(v.simRoot),
  wind: () => new Wind(),
  world: (v) => new World(v),
  ground: (v) => new Ground(v),
  light: (v) => new Light(v),
  sky: (v) => new SkyFeature(v),
  leaves: (v) => new LeafDetail(v),
  forest: (v) => new Forest(v),
  controllers: (v) => new Controllers(v.scene),
  occlusion: (v) => new Occlusion(v.renderer, v.scene),
  xrlight: (v) => new XrLight(v),
};
