// What a recording's header says of the input device (docs/headset.md, "Devices and their
// mappings"; the header's `device`, docs/replay-format.md): the WebXR input profile of the source
// that points, its target-ray mode, and grove's mapping of it onto the controller. Each field is
// 1 to 64 lowercase letters, digits and `-`, as the replay format requires.

const plain = (s) =>
  String(s ?? '')
    .toLowerCase()
    .replace(/[^a-z0-9-]/g, '-')
    .slice(0, 64) || 'unknown';

/** The header's device for an XR input source (or a description of one) and grove's mapping. */
export function deviceOf(source, mapping) {
  return { profile: plain(source?.profiles?.[0]), target_ray_mode: plain(source?.targetRayMode), mapping: plain(mapping) };
}
