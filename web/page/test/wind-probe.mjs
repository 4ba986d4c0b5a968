// The browser side of wind.test.mjs, bundled around the still page (web/page/still.mjs) by
// render.mjs's openStill: the page's wind GLSL (draw/wind.mjs) run on a model's own vertices by
// WebGL2 transform feedback, beside grove's CPU reference of the native renderer's displacement
// (the module's windDisplace), at the stage's wind of a tick: a lone tree's (its values as
// uniforms) and an InstancedMesh's (as the instanced attributes TreeWind packs).

import { setUp, stage } from '../still.mjs';
import {
  DISPLACE_GLSL,
  TREE_ATTRIBUTES,
  TREE_GLSL,
  TreeWind,
  WIND_GLSL,
  windUniforms,
  setWind,
} from '../draw/wind.mjs';

const VERTEX = (instanced) => `#version 300 es
${instanced ? '#define USE_INSTANCING' : ''}
#define attribute in
${WIND_GLSL}
${TREE_GLSL}
in vec3 position;
out vec3 world;
void main() {
	vec3 transformed = position;
	${DISPLACE_GLSL}
	world = treeOrigin + wind_rotate_y( transformed * treeScale, treeYaw );
	gl_Position = vec4( 0.0 );
}`;
const FRAGMENT = `#version 300 es
precision highp float;
out vec4 colour;
void main() { colour = vec4( 0.0 ); }`;

function program(gl, instanced) {
  const p = gl.createProgram();
  for (const [type, source] of [
    [gl.VERTEX_SHADER, VERTEX(instanced)],
    [gl.FRAGMENT_SHADER, FRAGMENT],
  ]) {
    const s = gl.createShader(type);
    gl.shaderSource(s, source);
    gl.compileShader(s);
    if (!gl.getShaderParameter(s, gl.COMPILE_STATUS)) throw new Error(gl.getShaderInfoLog(s));
    gl.attachShader(p, s);
  }
  gl.transformFeedbackVaryings(p, ['world'], gl.SEPARATE_ATTRIBS);
  gl.linkProgram(p);
  if (!gl.getProgramParameter(p, gl.LINK_STATUS)) throw new Error(gl.getProgramInfoLog(p));
  return p;
}

function uniform(gl, p, name, value) {
  const at = gl.getUniformLocation(p, name);
  if (at === null) return;
  if (typeof value === 'number') (name === 'windModel' ? gl.uniform1i : gl.uniform1f).call(gl, at, value);
  else if (value.isVector2) gl.uniform2f(at, value.x, value.y);
  else gl.uniform3f(at, value.x, value.y, value.z);
}

/**
 * The GLSL's world positions of `points` ([x, y, z, h, r, b, phase] each) for the tree and the
 * wind set, its values as uniforms or (`instanced`) as attributes.
 */
function glsl(points, tree, instanced) {
  const gl = document.createElement('canvas').getContext('webgl2');
  const p = program(gl, instanced);
  gl.useProgram(p);
  // An InstancedMesh's tree: its packed attributes, the same for every vertex.
  const wind = new TreeWind();
  wind.set(tree);
  const packed = new Float32Array(12);
  wind.pack(packed, 0);
  TREE_ATTRIBUTES.forEach((name, k) => {
    const at = gl.getAttribLocation(p, name);
    if (at >= 0) gl.vertexAttrib4fv(at, packed.subarray(4 * k, 4 * k + 4));
  });
  for (const [name, u] of Object.entries(windUniforms)) uniform(gl, p, name, u.value);
  uniform(gl, p, 'treeOrigin', { x: tree.position[0], y: tree.position[1], z: tree.position[2] });
  uniform(gl, p, 'treeYaw', tree.yaw);
  uniform(gl, p, 'treeScale', tree.scale);
  uniform(gl, p, 'treeBend', { isVector2: true, x: tree.wind?.bend[0] ?? 0, y: tree.wind?.bend[1] ?? 0 });
  uniform(gl, p, 'treeGain', tree.wind?.gain ?? 0);
  uniform(gl, p, 'treePhase', tree.wind?.phase ?? 0);
  uniform(gl, p, 'treeKeep', 1); // every leaf drawn at its size (leaves.mjs): the wind alone moves them
  const attribute = (name, size, data) => {
    const b = gl.createBuffer();
    gl.bindBuffer(gl.ARRAY_BUFFER, b);
    gl.bufferData(gl.ARRAY_BUFFER, data, gl.STATIC_DRAW);
    const at = gl.getAttribLocation(p, name);
    gl.enableVertexAttribArray(at);
    gl.vertexAttribPointer(at, size, gl.FLOAT, false, 0, 0);
  };
  attribute('position', 3, new Float32Array(points.flatMap((q) => q.slice(0, 3))));
  attribute('_wind', 4, new Float32Array(points.flatMap((q) => q.slice(3))));
  const out = gl.createBuffer();
  gl.bindBuffer(gl.TRANSFORM_FEEDBACK_BUFFER, out);
  gl.bufferData(gl.TRANSFORM_FEEDBACK_BUFFER, points.length * 12, gl.STREAM_READ);
  gl.bindBufferBase(gl.TRANSFORM_FEEDBACK_BUFFER, 0, out);
  gl.enable(gl.RASTERIZER_DISCARD);
  gl.beginTransformFeedback(gl.POINTS);
  gl.drawArrays(gl.POINTS, 0, points.length);
  gl.endTransformFeedback();
  gl.disable(gl.RASTERIZER_DISCARD);
  const result = new Float32Array(points.length * 3);
  gl.getBufferSubData(gl.TRANSFORM_FEEDBACK_BUFFER, 0, result);
  return Array.from({ length: points.length }, (_, i) => [result[3 * i], result[3 * i + 1], result[3 * i + 2]]);
}

/** Every `step`-th vertex of the model with its _WIND channels. */
function samples(models, count) {
  const points = [];
  models.models.get('model').traverse((o) => {
    const pos = o.geometry?.attributes.position;
    const wind = o.geometry?.attributes._wind;
    if (!pos || !wind) return;
    o.updateWorldMatrix(true, false);
    const step = Math.max(1, Math.floor(pos.count / count));
    for (let i = 0; i < pos.count; i += step)
      points.push([pos.getX(i), pos.getY(i), pos.getZ(i), wind.getX(i), wind.getY(i), wind.getZ(i), wind.getW(i)]);
  });
  return points;
}

/**
 * At each of `ticks` of the stage's study wind: `count` or so of the model's vertices displaced
 * by the page's GLSL and by grove's CPU reference, and the largest distance between the two
 * and the largest sway from rest (metres).
 */
window.windProbe = async ({ model, ticks, count = 400 }) => {
  const { grove } = await setUp();
  const out = [];
  for (const tick of ticks) {
    const { models, sim } = await stage(model, { aspect: 4 / 3, tick });
    const snap = sim.snapshot();
    sim.free();
    setWind(snap.wind);
    const tree = snap.trees[0];
    const points = samples(models, count);
    const cpu = grove.windDisplace({ wind: snap.wind, tree, points });
    const [page, instanced] = [false, true].map((i) => glsl(points, tree, i));
    const rest = grove.windDisplace({ wind: { ...snap.wind, strength: 0 }, tree: { ...tree, wind: null }, points });
    const dist = (a, b) => Math.hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
    out.push({
      tick,
      points: points.length,
      gust: snap.wind.gust,
      error: Math.max(...[...page, ...instanced].map((q, i) => dist(q, cpu[i % points.length]))),
      instanced: Math.max(...instanced.map((q, i) => dist(q, cpu[i]))),
      sway: Math.max(...cpu.map((q, i) => dist(q, rest[i]))),
    });
  }
  return out;
};
