// The room in AR and the study's frame: where the participant starts and the floor the session
// found define the simulation's coordinates, and the floor (and any other horizontal plane the
// headset found) becomes the scene the session is recorded on (docs/headset.md, "AR"): the page
// finds them here, the module builds the scene from them (grove.roomScene, systems/src/room.rs).
//
// The simulation's frame is the study scene's: the participant starts at (0, y, 6) looking
// towards -Z, and the ground is y = 0. A reference space offset from the session's `local-floor`
// by `simOffset` gives every pose directly in that frame, so the task's targets lie where the
// study puts them relative to where the participant stands.

/** Where the study scene's camera stands, metres (assets/scenes/study.ron). */
export const START = { x: 0, z: 6 };

/** The heading of an orientation: the angle about +Y that turns -Z into its horizontal forward. */
export function yawOf(q) {
  // forward = q * (0, 0, -1)
  const fx = -2 * (q.x * q.z + q.w * q.y);
  const fz = -(1 - 2 * (q.x * q.x + q.y * q.y));
  return Math.atan2(-fx, -fz);
}

/**
 * The rigid transform (position {x, y, z}, orientation {x, y, z, w}) that places the simulation's
 * frame in the session's reference space: the head at `head` (a position in that space) with
 * heading `yaw` becomes the study's start, and height `floorY` its ground.
 */
export function simOffset(head, yaw, floorY) {
  const s = Math.sin(yaw / 2);
  const c = Math.cos(yaw / 2);
  // position = head (on the floor) + R(yaw) * (-START.x, 0, -START.z)
  const cy = Math.cos(yaw);
  const sy = Math.sin(yaw);
  const lx = -START.x;
  const lz = -START.z;
  return {
    position: { x: head.x + cy * lx + sy * lz, y: floorY, z: head.z - sy * lx + cy * lz },
    orientation: { x: 0, y: s, z: 0, w: c },
  };
}

/** A point of the simulation's frame in the session's reference space (for tests and overlays). */
export function toSession(offset, p) {
  const yaw = 2 * Math.atan2(offset.orientation.y, offset.orientation.w);
  const c = Math.cos(yaw);
  const s = Math.sin(yaw);
  return { x: offset.position.x + c * p.x + s * p.z, y: offset.position.y + p.y, z: offset.position.z - s * p.x + c * p.z };
}

/**
 * The horizontal planes of an XR frame (plane-detection) in the simulation's frame: `space` is
 * the simulation's reference space. Each as { label, y, points, area }.
 */
export function horizontalPlanes(frame, space) {
  const out = [];
  for (const plane of frame?.detectedPlanes ?? []) {
    if (plane.orientation && plane.orientation !== 'horizontal') continue;
    const pose = frame.getPose(plane.planeSpace, space);
    if (!pose) continue;
    const m = pose.transform.matrix;
    const points = plane.polygon.map((p) => ({ x: m[0] * p.x + m[4] * p.y + m[8] * p.z + m[12], y: m[1] * p.x + m[5] * p.y + m[9] * p.z + m[13], z: m[2] * p.x + m[6] * p.y + m[10] * p.z + m[14] }));
    if (points.length < 3) continue;
    let area = 0;
    for (let i = 0; i < points.length; i++) {
      const a = points[i];
      const b = points[(i + 1) % points.length];
      area += a.x * b.z - b.x * a.z;
    }
    const y = points.reduce((s, p) => s + p.y, 0) / points.length;
    out.push({ label: (plane.semanticLabel ?? 'plane').replace(/[^a-z_]/gi, '').toLowerCase() || 'plane', y, points, area: Math.abs(area) / 2 });
  }
  return out;
}

/** The floor among horizontal planes: one labelled floor, else the lowest of at least 1 m². */
export function floorOf(planes) {
  const labelled = planes.filter((p) => p.label === 'floor').sort((a, b) => b.area - a.area)[0];
  if (labelled) return labelled;
  return planes.filter((p) => p.area >= 1).sort((a, b) => a.y - b.y)[0] ?? null;
}

/**
 * A pose of the session's reference space in the simulation's frame: `offset` (simOffset) is the
 * simulation's frame in that space, so the pose is offset⁻¹ · pose. Plain numbers in and out
 * (position {x, y, z}, orientation {x, y, z, w}). The page applies the offset itself rather than
 * through an offset reference space, which some runtimes (the test emulator among them) do not
 * offset.
 */
export function toSim(offset, position, orientation) {
  const yaw = 2 * Math.atan2(offset.orientation.y, offset.orientation.w);
  const c = Math.cos(yaw);
  const s = Math.sin(yaw);
  const dx = position.x - offset.position.x;
  const dz = position.z - offset.position.z;
  // R(yaw)⁻¹ = R(-yaw): (x, z) -> (x c - z s, x s + z c)
  const p = { x: c * dx - s * dz, y: position.y - offset.position.y, z: s * dx + c * dz };
  if (!orientation) return { position: p };
  // q_sim = conj(q_offset) * q, with q_offset = (0, sy, 0, cy) about +Y.
  const sy = -offset.orientation.y;
  const cy = offset.orientation.w;
  const { x, y, z, w } = orientation;
  const o = { x: cy * x + sy * z, y: cy * y + sy * w, z: cy * z - sy * x, w: cy * w - sy * y };
  return { position: p, orientation: o };
}
