// One invocation a ray. SCANS: poses x beams (result p * beams + b); else explicit rays.
layout(local_size_x = GROUP_SIZE) in;

#if SCANS
layout(std430, binding = BIND_IN0) readonly buffer Poses { vec4 pose[]; };  // 3 rows (R | t) a pose
layout(std430, binding = BIND_IN1) readonly buffer Beams { vec4 beam[]; };  // 2 a beam: (d, t0), (t1, 0, 0, 0)
uniform uint beams;
#else
layout(std430, binding = BIND_IN0) readonly buffer Origins { vec4 ray_o[]; };  // (o, t0)
layout(std430, binding = BIND_IN1) readonly buffer Dirs { vec4 ray_d[]; };     // (d, t1)
#endif
layout(std430, binding = BIND_HITS) writeonly buffer Hits { uvec2 hit[]; };  // range bits, Mesh triangle

uniform uint count;  // rays in this batch
uniform uint backface_is_solid;
uniform uint miss_is_max_range;

void main() {
  uint i = gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x;
  if (i >= count) return;
#if SCANS
  uint p = i / beams, b = i - p * beams;
  vec4 r0 = pose[3u * p], r1 = pose[3u * p + 1u], r2 = pose[3u * p + 2u];
  vec4 bd = beam[2u * b];
  vec3 o = vec3(r0.w, r1.w, r2.w);
  vec3 d = vec3(dot(r0.xyz, bd.xyz), dot(r1.xyz, bd.xyz), dot(r2.xyz, bd.xyz));
  float t0 = bd.w, t1 = beam[2u * b + 1u].x;
#else
  vec4 ro = ray_o[i], rd = ray_d[i];
  vec3 o = ro.xyz, d = rd.xyz;
  float t0 = ro.w, t1 = rd.w;
#endif
  Hit h = trace(o, d, t0, t1);
  if (h.id == kNoHit)
    hit[i] = uvec2(miss_is_max_range != 0u ? floatBitsToUint(t1) : kInfBits, kNoHit);
  else
    hit[i] = uvec2(floatBitsToUint(h.back && backface_is_solid != 0u ? t0 : h.t), h.id);
}
