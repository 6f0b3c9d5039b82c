// The map's BVH (gpu/bvh.hpp) and the two walks over it every program shares: the closest hit
// of a ray in a window, and whether any triangle lies nearer than r to a point. Prepended:
// "#version 310 es" and the program's defines (raycast/gpu.cpp).
precision highp float;
precision highp int;

struct Node {  // both children's boxes; w: the children's references (gpu/bvh.hpp)
  vec4 lmin;    // w: left reference: >= 0 inner node, < 0 leaf (k = -ref - 1: first k >> 4, count k & 15)
  vec4 lmax;    // w: right reference
  vec4 rmin;
  vec4 rmax;
};
layout(std430, binding = BIND_NODES) readonly buffer Nodes { Node nodes[]; };
layout(std430, binding = BIND_VERTS) readonly buffer Verts { vec4 verts[]; };  // 3 a triangle, leaf order
layout(std430, binding = BIND_TRI_IDS) readonly buffer TriIds { uint tri_id[]; };  // Mesh index, leaf order

const uint kNoHit = 0xFFFFFFFFu;
const uint kInfBits = 0x7F800000u;
const int kStack = 64;  // > the builder's maxDepth (48) + 1
const float kFar = 3.0e38;

struct Hit {
  float t;
  uint id;    // Mesh triangle, kNoHit for none
  bool back;  // the ray met the triangle's back face
};

// Closest hit with t in [t0, t1]. Triangles: watertight test (Woop, Benthin, Wald 2013), so no
// ray slips through a shared edge, as Embree's robust mode. Ties at one distance are decided as
// Embree's tie filter decides them (raycast/embree.cpp), whatever order the walk meets the
// triangles in: of two coplanar faces facing opposite ways (touching solids: an exit face and the
// neighbour's entry face) the back face; of a front and a back face meeting at an edge or vertex,
// the front face (the ray touched the surface; its origin is not inside a solid); then the lower
// triangle index. "One distance" is within tie_tol, as in Embree (CoincidentFaces::tolerance():
// 1e-5 m, or a few float steps at the map's largest coordinate).
uniform float tie_tol;
bool replaces(float t, vec3 nrm, bool back, uint id, Hit h, vec3 best_n) {
  if (h.id == kNoHit) return true;
  if (abs(t - h.t) > tie_tol) return t < h.t;
  if (back != h.back) return dot(nrm, best_n) < -0.999 ? back : !back;
  return id < h.id;
}

// Entry distance of the ray into box [lo, hi] within [t0, t1], or kFar when it misses.
float enterBox(vec3 lo, vec3 hi, vec3 o, vec3 inv, float t0, float t1) {
  vec3 ta = (lo - o) * inv, tb = (hi - o) * inv;
  vec3 tn = min(ta, tb), tf = max(ta, tb);
  float enter = max(max(tn.x, tn.y), max(tn.z, t0));
  float leave = min(min(tf.x, tf.y), min(tf.z, t1));
  return enter <= leave ? enter : kFar;
}

Hit trace(vec3 o, vec3 d, float t0, float t1) {
  Hit h = Hit(t1, kNoHit, false);
  if (!(t0 <= t1)) return h;
  vec3 ad = abs(d);
  int kz = ad.x > ad.y ? (ad.x > ad.z ? 0 : 2) : (ad.y > ad.z ? 1 : 2);
  int kx = kz == 2 ? 0 : kz + 1;
  int ky = kx == 2 ? 0 : kx + 1;
  if (d[kz] < 0.0) { int s = kx; kx = ky; ky = s; }
  float sx = d[kx] / d[kz], sy = d[ky] / d[kz], sz = 1.0 / d[kz];
  // Zero components get a huge finite inverse: 0 * inf would be NaN in the slab test.
  vec3 safe = mix(d, sign(d + 1e-37) * 1e-30, lessThan(ad, vec3(1e-30)));
  vec3 inv = 1.0 / safe;
  vec3 best_n = vec3(0.0);
  // Children are tested where the walk stands and the nearer is walked first; an entry kept on
  // the stack is skipped once a hit nearer than it is known.
  int stack[kStack];
  float entry[kStack];
  int sp = 0;
  stack[0] = 0;
  entry[0] = t0;
  sp = 1;
  while (sp > 0) {
    --sp;
    float reach = min(h.t + tie_tol, t1);  // a tie may lie a tolerance beyond the kept hit
    if (entry[sp] > reach) continue;
    int ref = stack[sp];
    if (ref >= 0) {
      Node n = nodes[ref];
      float el = enterBox(n.lmin.xyz, n.lmax.xyz, o, inv, t0, reach);
      float er = enterBox(n.rmin.xyz, n.rmax.xyz, o, inv, t0, reach);
      int l = floatBitsToInt(n.lmin.w), r = floatBitsToInt(n.lmax.w);
      if (el > er) { float te = el; el = er; er = te; int tr = l; l = r; r = tr; }
      if (er < kFar && sp < kStack) { stack[sp] = r; entry[sp] = er; ++sp; }
      if (el < kFar && sp < kStack) { stack[sp] = l; entry[sp] = el; ++sp; }
      continue;
    }
    int k = -ref - 1;
    int first = k >> 4, last = first + (k & 15);
    for (int i = first; i < last; ++i) {
      vec3 v0 = verts[3 * i].xyz, v1 = verts[3 * i + 1].xyz, v2 = verts[3 * i + 2].xyz;
      vec3 A = v0 - o, B = v1 - o, C = v2 - o;
      float ax = A[kx] - sx * A[kz], ay = A[ky] - sy * A[kz];
      float bx = B[kx] - sx * B[kz], by = B[ky] - sy * B[kz];
      float cx = C[kx] - sx * C[kz], cy = C[ky] - sy * C[kz];
      float U = cx * by - cy * bx, V = ax * cy - ay * cx, W = bx * ay - by * ax;
      if ((U < 0.0 || V < 0.0 || W < 0.0) && (U > 0.0 || V > 0.0 || W > 0.0)) continue;
      float det = U + V + W;
      if (det == 0.0) continue;
      float t = (U * (sz * A[kz]) + V * (sz * B[kz]) + W * (sz * C[kz])) / det;
      if (!(t >= t0 && t <= min(h.t + tie_tol, t1))) continue;
      vec3 nrm = normalize(cross(v1 - v0, v2 - v0));
      bool back = dot(nrm, d) > 0.0;
      uint id = tri_id[i];
      if (!replaces(t, nrm, back, id, h, best_n)) continue;
      h = Hit(t, id, back);
      best_n = nrm;
    }
  }
  return h;
}

// Closest point of triangle abc to p (Ericson, Real-Time Collision Detection, 5.1.5).
vec3 closestOnTriangle(vec3 p, vec3 a, vec3 b, vec3 c) {
  vec3 ab = b - a, ac = c - a, ap = p - a;
  float d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0.0 && d2 <= 0.0) return a;
  vec3 bp = p - b;
  float d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0.0 && d4 <= d3) return b;
  float vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return a + ab * (d1 / (d1 - d3));
  vec3 cp = p - c;
  float d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0.0 && d5 <= d6) return c;
  float vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return a + ac * (d2 / (d2 - d6));
  float va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0) return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
  float den = 1.0 / (va + vb + vc);
  return a + ab * (vb * den) + ac * (vc * den);
}

// Squared distance from p to box [lo, hi] (0 inside).
float boxDist2(vec3 p, vec3 lo, vec3 hi) {
  vec3 q = clamp(p, lo, hi);
  return dot(q - p, q - p);
}

// Whether some triangle lies nearer than r to p.
bool anyWithin(vec3 p, float r) {
  int stack[kStack];
  int sp = 1;
  stack[0] = 0;
  while (sp > 0) {
    int ref = stack[--sp];
    if (ref >= 0) {
      Node n = nodes[ref];
      if (boxDist2(p, n.lmin.xyz, n.lmax.xyz) < r * r && sp < kStack) stack[sp++] = floatBitsToInt(n.lmin.w);
      if (boxDist2(p, n.rmin.xyz, n.rmax.xyz) < r * r && sp < kStack) stack[sp++] = floatBitsToInt(n.lmax.w);
      continue;
    }
    int k = -ref - 1;
    int first = k >> 4, last = first + (k & 15);
    for (int i = first; i < last; ++i) {
      vec3 c = closestOnTriangle(p, verts[3 * i].xyz, verts[3 * i + 1].xyz, verts[3 * i + 2].xyz);
      if (length(c - p) < r) return true;
    }
  }
  return false;
}
