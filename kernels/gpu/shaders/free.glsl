// Free-space queries, one invocation a point: inside a solid when the first surface met is a
// back face for most of three irregular directions (Embree's vote, raycast/embree.cpp), and
// clear when no triangle lies nearer than the clearance.
layout(local_size_x = GROUP_SIZE) in;

layout(std430, binding = BIND_IN0) readonly buffer Points { vec4 point[]; };
layout(std430, binding = BIND_HITS) writeonly buffer Free { uint free_out[]; };

uniform uint count;
uniform float clearance;

const vec3 kVote[3] = vec3[3](vec3(0.5377, 0.8314, 0.1397), vec3(-0.7071, 0.3162, -0.6325),
                              vec3(0.1925, -0.8660, 0.4615));

void main() {
  uint i = gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x;
  if (i >= count) return;
  vec3 p = point[i].xyz;
  int back = 0;
  for (int k = 0; k < 3; ++k) {
    Hit h = trace(p, kVote[k], 0.0, uintBitsToFloat(kInfBits));
    if (h.id != kNoHit && h.back) ++back;
  }
  bool ok = back < 2 && !(clearance > 0.0 && anyWithin(p, clearance));
  free_out[i] = ok ? 1u : 0u;
}
