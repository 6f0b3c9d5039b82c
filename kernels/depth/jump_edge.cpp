// Jump edges (flying pixels) by the angle between a neighbour edge and the view ray. A surface
// seen at a grazing angle g gives edges at about g to the ray; a pixel whose depth was mixed
// between a foreground and a background surface gives edges nearly along it. See stages.hpp.
// Dense loops over rows of 3D points (NaN where rejected: every comparison with NaN is false,
// so a missing neighbour is never a jump), which vectorise.
#include "stages.hpp"

#include <cmath>
#include <vector>

namespace polyloc::depth_detail {

namespace {

using F = float* __restrict;
using CF = const float* __restrict;

// Jump flags of the pairs (a, b) between row a (points ax, ay, az) and row b (bx, by, bz, already
// shifted to the partner): per line two bits, `nearer` (a jump to a nearer neighbour) and
// `farther`, set on both pixels of a jump.
void markPairs(CF ax, CF ay, CF az, CF bx, CF by, CF bz, float cos2, uint8_t* __restrict fa,
               uint8_t* __restrict fb, uint8_t nearer, uint8_t farther, int len) {
  for (int x = 0; x < len; ++x) {
    const float ex = bx[x] - ax[x], ey = by[x] - ay[x], ez = bz[x] - az[x];
    const float dot = ex * ax[x] + ey * ay[x] + ez * az[x];
    const float e2 = ex * ex + ey * ey + ez * ez;
    const float ray2 = ax[x] * ax[x] + ay[x] * ay[x] + az[x] * az[x];
    // cos^2(angle between edge and ray) = dot^2 / (|e|^2 |p|^2), without a division or a root.
    const uint8_t jump = dot * dot > cos2 * e2 * ray2 ? 1 : 0;
    const uint8_t b_farther = ez > 0.f ? 1 : 0;  // z is the depth
    fa[x] |= jump * (b_farther ? farther : nearer);
    fb[x] |= jump * (b_farther ? nearer : farther);
  }
}

}  // namespace

void rejectJumpEdges(const JumpEdgeFilter& c, const float* xn, const float* yn, Work& work) {
  if (!c.enabled) return;
  const int w = work.w, h = work.h;
  const size_t n = work.size();
  const float cos_min = static_cast<float>(std::cos(c.min_angle));
  const float cos2 = cos_min * cos_min;
  thread_local std::vector<float> px, py, pz;
  thread_local std::vector<uint8_t> flags;  // per pixel and line: a jump to a nearer / farther neighbour
  px.resize(n), py.resize(n), pz.resize(n);
  flags.assign(n, 0);
  // p_i = d_i (x_i, y_i, 1); the view ray is p_i itself (the camera at the origin).
  for (size_t i = 0; i < n; ++i) {
    const float d = work.depth[i];
    px[i] = d * xn[i], py[i] = d * yn[i], pz[i] = d;
  }
  // Lines: 0 along rows, 1 columns, 2 the diagonal down-right, 3 down-left.
  for (int v = 0; v < h; ++v) {
    const size_t r = size_t(v) * w;
    markPairs(&px[r], &py[r], &pz[r], &px[r + 1], &py[r + 1], &pz[r + 1], cos2, &flags[r], &flags[r + 1], 2, 1, w - 1);
    if (v + 1 == h) continue;
    const size_t d = r + w;
    markPairs(&px[r], &py[r], &pz[r], &px[d], &py[d], &pz[d], cos2, &flags[r], &flags[d], 8, 4, w);
    if (c.neighbours != 8) continue;
    markPairs(&px[r], &py[r], &pz[r], &px[d + 1], &py[d + 1], &pz[d + 1], cos2, &flags[r], &flags[d + 1], 32, 16, w - 1);
    markPairs(&px[r + 1], &py[r + 1], &pz[r + 1], &px[d], &py[d], &pz[d], cos2, &flags[r + 1], &flags[d], 128, 64, w - 1);
  }
  const bool any = c.mode == "any";
  for (size_t i = 0; i < n; ++i) {
    const uint8_t f = flags[i];
    // between: along one line a jump to a nearer neighbour and one to a farther one, as a pixel
    // with a depth mixed between a foreground and a background has; a thin foreground structure
    // (a chair leg) has farther neighbours on both sides and stays.
    const bool between = (f & 3) == 3 || (f & 12) == 12 || (f & 48) == 48 || (f & 192) == 192;
    if (any ? f != 0 : between) work.reject(i, DepthReject::kJumpEdge);
  }
}

}  // namespace polyloc::depth_detail
