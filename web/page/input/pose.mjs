// The page's one pose shape: `{ position: [x, y, z], rotation: [x, y, z, w] }` in the
// simulation's frame (metres, +Y up; the study's start at (0, 1.7, 6) looking towards -Z), as a
// snapshot's `head` and `controller.pose` have it. Every input source hands its pose in this
// shape, and the ray, the head, the panel's ray and the menu's pick are made from it; the
// session's reference space is turned into it once, here (`simPose`). The simulation consumes
// its numbers rounded to f32 (`f32Pose`), which is what the recording keeps, bit for bit.

import * as THREE from 'three';
import { toSim } from '../room.mjs';

/** A pose from a position {x, y, z} and an orientation {x, y, z, w} (an XRRigidTransform's, three.js's). */
export function poseOf(position, orientation) {
  return { position: [position.x, position.y, position.z], rotation: [orientation.x, orientation.y, orientation.z, orientation.w] };
}

/**
 * A transform of the session's reference space (an XRRigidTransform, or null) as a pose of the
 * simulation's frame: `offset` (room.mjs's simOffset) is that frame in the session's space;
 * without one the two frames are the same.
 */
export function simPose(transform, offset) {
  if (!transform) return null;
  const t = offset ? toSim(offset, transform.position, transform.orientation) : transform;
  return poseOf(t.position, t.orientation);
}

/** A pose with every number rounded to f32 (Math.fround): what the module parses and the recording keeps. */
export function f32Pose(pose) {
  return { position: pose.position.map(Math.fround), rotation: pose.rotation.map(Math.fround) };
}

/** A key that is equal for equal f32 poses (to send a pose only when it changed). */
export function poseKey(pose) {
  return pose.position.join(',') + ';' + pose.rotation.join(',');
}

/** The unit direction a pose's -Z points along, [x, y, z]. */
export function forward(rotation) {
  const d = new THREE.Vector3(0, 0, -1).applyQuaternion(new THREE.Quaternion(...rotation));
  return [d.x, d.y, d.z];
}

/** A pose's ray: [origin, direction], arrays. */
export function rayOf(pose) {
  return [pose.position, forward(pose.rotation)];
}

/** A pose's position as {x, y, z} (where a label turns to). */
export function pointOf(pose) {
  const [x, y, z] = pose.position;
  return { x, y, z };
}

/**
 * The rotation [x, y, z, w] that turns -Z into the unit direction `d` ([x, y, z]) keeping +X
 * level (no roll), as the simulation's `rotation_towards` does: a yaw about +Y, then a pitch.
 */
export function lookRotation(d) {
  const yaw = Math.atan2(-d[0], -d[2]);
  const pitch = Math.asin(Math.max(-1, Math.min(1, d[1])));
  const sy = Math.sin(yaw / 2);
  const cy = Math.cos(yaw / 2);
  const sp = Math.sin(pitch / 2);
  const cp = Math.cos(pitch / 2);
  // q = qYaw * qPitch
  return [cy * sp, sy * cp, -sy * sp, cy * cp];
}

/**
 * A ray carried by a hand: `ray0` (a pose) as it was when the hand's grip was at `grip0`, moved
 * and turned with the grip to `grip` (the rigid motion grip · grip0⁻¹ applied to the ray). Without
 * a grip, the ray as it was.
 */
export function carried(ray0, grip0, grip) {
  if (!grip0 || !grip) return ray0;
  const q0 = new THREE.Quaternion(...grip0.rotation);
  const q = new THREE.Quaternion(...grip.rotation);
  const turn = q.clone().multiply(q0.clone().invert());
  const p = new THREE.Vector3(...ray0.position).sub(new THREE.Vector3(...grip0.position)).applyQuaternion(turn).add(new THREE.Vector3(...grip.position));
  const r = turn.multiply(new THREE.Quaternion(...ray0.rotation)).normalize();
  return { position: [p.x, p.y, p.z], rotation: [r.x, r.y, r.z, r.w] };
}

/** A pose moved by `d` ([x, y, z]), its rotation kept. */
export function shifted(pose, d) {
  return { position: pose.position.map((v, i) => v + d[i]), rotation: pose.rotation };
}
