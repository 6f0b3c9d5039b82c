// The beam model per pose (raycast/scan_score.hpp, scoreHits): one invocation sums the
// log-densities of its pose's beams in beam order, from the ranges the ray pass left on the GPU.
layout(local_size_x = GROUP_SIZE) in;

layout(std430, binding = BIND_HITS) readonly buffer Hits { uvec2 hit[]; };
layout(std430, binding = BIND_TERMS) readonly buffer Terms { vec4 term[]; };  // 2 a beam: (z, miss, short, hit_scale), (half_inv_var, 0, 0, 0)
layout(std430, binding = BIND_TABLES) readonly buffer Tables { float table[]; };  // hit density, then its log with p_rand
layout(std430, binding = BIND_SUMS) writeonly buffer Sums { float sums[]; };

uniform uint poses;
uniform uint beams;
uniform uint table_size;  // 0: no table
uniform float inv_step;
uniform float p_rand;

void main() {
  uint p = gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x;
  if (p >= poses) return;
  float s = 0.0;
  for (uint i = 0u; i < beams; ++i) {
    uint bits = hit[p * beams + i].x;
    vec4 t = term[2u * i];
    if ((bits & 0x7FFFFFFFu) >= 0x7F800000u) {  // no hit in the window
      s += t.y;
      continue;
    }
    float d = t.x - uintBitsToFloat(bits);
    if (table_size > 0u) {
      float x = abs(d) * inv_step;
      uint k = uint(min(x, float(table_size - 2u)));
      float f = min(x - float(k), 1.0);
      if (d >= 0.0) s += table[table_size + k] + f * (table[table_size + k + 1u] - table[table_size + k]);
      else s += log(table[k] + f * (table[k + 1u] - table[k]) + t.z + p_rand);
      continue;
    }
    s += log(t.w * exp(-term[2u * i + 1u].x * d * d) + (d < 0.0 ? t.z : 0.0) + p_rand);
  }
  sums[p] = s;
}
