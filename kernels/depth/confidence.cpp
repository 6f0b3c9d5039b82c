// The confidence filter (eq. 6.4 of the thesis, with the changes described at ConfidenceFilter
// in polyloc/depth/config.hpp). The image is padded by reach + 1 pixels of "outside", so that no
// neighbour access needs a bounds check, and each iteration runs a row at a time over plain
// float arrays: where the nearest kept pixels are in each direction, the 12 predictions
// (4 two-sided, 8 one-sided) and their exponents, then cv::exp over them all. Branch-free row
// loops vectorise; the first version, a per-pixel search, was 3x slower.
#include "stages.hpp"

#include <opencv2/core.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

namespace polyloc::depth_detail {

namespace {

constexpr int kDirs = 8;

// Per-thread buffers: a frame reuses them, so the filter does not allocate once warm.
struct Scratch {
  std::vector<float> q, a, c, cand, kept, next;  // padded image
  std::vector<float> wc[kDirs];  // padded: colour weight of the pair (i, i + step * off[2k]), k*2 + step-1
  // A row, per direction: steps to the nearest two kept pixels, q there, the colour weight of the
  // nearest, whether the search is still open after two steps.
  std::vector<float> n1[kDirs], n2[kDirs], q1[kDirs], q2[kDirs], cw[kDirs], open;
  std::vector<float> e, sum, cnt;  // a row per prediction: exponent; per pixel: totals
  std::vector<int> holes, hole_start;
};

// The row kernels. __restrict and no branches (selects on loaded values) let them vectorise;
// each is built for AVX2 and for the baseline, and the loader picks what the CPU has. Not under
// the sanitizers (make sanitize): the loader runs the ifunc resolver before their runtime is up,
// and the instrumented resolver crashes.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__SANITIZE_THREAD__) && !defined(__SANITIZE_ADDRESS__)
#define POLYLOC_ROW_KERNEL __attribute__((target_clones("avx2", "default")))
#else
#define POLYLOC_ROW_KERNEL
#endif
using F = float* __restrict;
using CF = const float* __restrict;

// The nearest two kept pixels along one direction, at steps 1 and 2 (k1, k2: `kept` shifted by
// one and two steps; 1 kept, 0 not, -1 outside the image): their steps n1, n2 (0: none yet),
// q there, and the colour weight of the nearest (w1, w2 at steps 1 and 2; COLOUR false: 1).
// Returns how many searches are still open (no two found, both steps inside the image); those
// are flagged in open_at.
template <bool COLOUR>
POLYLOC_ROW_KERNEL int nearestTwo(CF k1, CF k2, CF q1s, CF q2s, CF w1, CF w2, F n1, F n2, F q1, F q2, F cw,
                                  F open_at, int len) {
  int open = 0;  // an integer count: a float reduction would not vectorise without -ffast-math
  for (int x = 0; x < len; ++x) {
    // Arithmetic on 0/1 flags rather than branches (q and the weights are finite).
    const float a = k1[x], b = k2[x], qa = q1s[x], qb = q2s[x];
    const float fa = a > 0.f ? 1.f : 0.f, fb = b > 0.f ? 1.f : 0.f, both = fa * fb, only_b = (1.f - fa) * fb;
    n1[x] = fa + 2.f * only_b;
    n2[x] = 2.f * both;
    q1[x] = fa * qa + only_b * qb;
    q2[x] = both * qb;
    if constexpr (COLOUR) cw[x] = fa * w1[x] + (1.f - fa) * w2[x];
    const float inside = (a >= 0.f ? 1.f : 0.f) * (b >= 0.f ? 1.f : 0.f);
    open_at[x] = (1.f - both) * inside;
    open += int(open_at[x]);
  }
  return open;
}

// Exponent -w z^2 of each prediction q_hat: z^2 = (q - q_hat)^2 A / gain^2, w the colour weight;
// -80 (exp: nothing) where the prediction does not exist. cnt counts those that do.
POLYLOC_ROW_KERNEL void twoSided(CF na, CF nb, CF qa, CF qb, CF q, CF A, CF cw, F e, F cnt, int len) {
  for (int x = 0; x < len; ++x) {
    // q_hat = (qa nb + qb na) / (na + nb) and gain^2 = 1 + (na^2 + nb^2) / (na + nb)^2, scaled by
    // (na + nb) and (na + nb)^2 so that one division remains.
    const float s = na[x] + nb[x];
    const float R = q[x] * s - (qa[x] * nb[x] + qb[x] * na[x]);
    const float G = s * s + na[x] * na[x] + nb[x] * nb[x];
    const float ok = (na[x] > 0.f ? 1.f : 0.f) * (nb[x] > 0.f ? 1.f : 0.f);
    e[x] = ok > 0.f ? -std::min(R * R * A[x] / std::max(G, 1.f), 80.f) * cw[x] : -80.f;
    cnt[x] += ok;
  }
}

POLYLOC_ROW_KERNEL void oneSided(CF na, CF nb, CF qa, CF qb, CF q, CF A, CF cw, F e, F cnt, int len) {
  for (int x = 0; x < len; ++x) {
    // q_hat = qa + (qa - qb) t with t = na / (nb - na), gain^2 = 1 + (1 + t)^2 + t^2; scaled by
    // (nb - na) and its square.
    const float g = nb[x] - na[x];
    const float R = (q[x] - qa[x]) * g - (qa[x] - qb[x]) * na[x];
    const float G = g * g + nb[x] * nb[x] + na[x] * na[x];
    const float ok = nb[x] > 0.f ? 1.f : 0.f;
    e[x] = ok > 0.f ? -std::min(R * R * A[x] / std::max(G, 1.f), 80.f) * cw[x] : -80.f;
    cnt[x] += ok;
  }
}

POLYLOC_ROW_KERNEL void adjacent(CF na, CF qa, CF q, CF A, CF cw, F e, F cnt, int len) {
  for (int x = 0; x < len; ++x) {
    const float r = q[x] - qa[x];
    const float ok = na[x] == 1.f ? 1.f : 0.f;
    e[x] = ok > 0.f ? -std::min(r * r * A[x] * 0.5f, 80.f) * cw[x] : -80.f;
    cnt[x] += ok;
  }
}

POLYLOC_ROW_KERNEL void addRow(CF e, F sum, int len) {
  for (int x = 0; x < len; ++x) sum[x] += e[x];
}

float colourDist2(const float* c, int ch, size_t i, size_t j) {
  float d2 = 0.f;
  for (int k = 0; k < ch; ++k) {
    const float d = c[i * ch + k] - c[j * ch + k];
    d2 += d * d;
  }
  return d2;
}

// The colour term c per padded pixel (channels interleaved); 0 channels when there is none.
int fillColour(const ConfidenceFilter& cf, const DepthFrameView& f, int pad, int pw, int ph, std::vector<float>& c) {
  const bool rgb = f.rgb && (cf.colour == "auto" || cf.colour == "rgb");
  const bool amp = !rgb && f.amplitude && (cf.colour == "auto" || cf.colour == "amplitude");
  const int ch = rgb ? 3 : amp ? 1 : 0;
  if (ch == 0) return 0;
  c.assign(size_t(pw) * ph * ch, 0.f);
  for (int v = 0; v < f.height; ++v)
    for (int u = 0; u < f.width; ++u) {
      const size_t i = size_t(v) * f.width + u, p = size_t(v + pad) * pw + u + pad;
      if (rgb) {
        for (int k = 0; k < 3; ++k) c[p * 3 + k] = f.rgb[i * 3 + k] * (1.f / 255.f);
      } else {
        // log: amplitude falls with 1/r^2 and with reflectivity; a ratio compares like with like.
        const float a = f.amplitude[i];
        c[p] = std::log(std::isfinite(a) ? std::max(a, 1e-6f) : 1e-6f);
      }
    }
  return ch;
}

}  // namespace

void rejectLowConfidence(const ConfidenceFilter& cf, const DepthFrameView& frame, Work& work) {
  if (!cf.enabled || cf.iterations <= 0) return;
  thread_local Scratch scratch;
  Scratch& s = scratch;  // one TLS look-up
  const bool slope = cf.prediction == "slope";
  const int reach = slope ? std::max(cf.reach, 1) : 1;
  const int w = work.w, h = work.h, pad = reach + 1, pw = w + 2 * pad, ph = h + 2 * pad;
  const size_t pn = size_t(pw) * ph;

  // Inverse depth q (0: nothing) and the scale A that turns a residual in q into a squared
  // z-score: dd ~ dq d^2 (first order), so z^2 = dq^2 d^4 / (sigma noise(d))^2 / gain^2.
  // kept: 1 kept, 0 not (or no measurement), -1 outside the image (ends a neighbour search).
  s.q.assign(pn, 0.f), s.a.assign(pn, 0.f), s.cand.assign(pn, 0.f), s.kept.assign(pn, -1.f);
  const float k = static_cast<float>(cf.sigma);
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w; ++u) {
      const size_t p = size_t(v + pad) * pw + u + pad;
      const float d = work.depth[size_t(v) * w + u];
      s.kept[p] = 0.f;
      if (std::isnan(d)) continue;
      const float sd = k * static_cast<float>(cf.noise + (cf.noise_per_m + cf.noise_per_m2 * d) * d);
      s.q[p] = 1.f / d, s.a[p] = d * d * d * d / (sd * sd), s.cand[p] = s.kept[p] = 1.f;
    }
  s.next = s.kept;

  // Directions in opposite pairs: (0, 1) along rows, (2, 3) columns, (4, 5) and (6, 7) diagonals.
  const ptrdiff_t off[kDirs] = {1, -1, pw, -pw, pw + 1, -(pw + 1), pw - 1, -(pw - 1)};
  const int step_of[kDirs][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}, {1, 1}, {-1, -1}, {-1, 1}, {1, -1}};

  // Colour weights w_ij = exp(-|c_i - c_j|^2 / sigma_c) of the pixels one and two steps apart,
  // once per frame (the opposite direction reads the same pair from the other end).
  const int ch = fillColour(cf, frame, pad, pw, ph, s.c);
  const float inv_sc = static_cast<float>(1.0 / cf.sigma_c);
  if (ch) {
    for (int dir = 0; dir < kDirs; dir += 2)
      for (int step = 1; step <= 2; ++step) {
        std::vector<float>& wc = s.wc[dir + step - 1];
        wc.assign(pn, 0.f);
        const ptrdiff_t o = step * off[dir];
        for (size_t i = 2 * size_t(pw); i + o < pn; ++i) wc[i] = -colourDist2(s.c.data(), ch, i, i + o) * inv_sc;
        cv::Mat m(1, int(pn), CV_32F, wc.data());
        cv::exp(m, m);
      }
  }
  auto colourAt = [&](int dir, int step) {  // weights of (x, x + step * off[dir]) for a row, at x
    const int pair = dir & ~1;
    const float* wc = s.wc[pair + step - 1].data();
    return dir % 2 == 0 ? wc : wc - step * off[pair];
  };

  const int n_pred = slope ? 12 : 8;
  for (int dir = 0; dir < kDirs; ++dir)
    for (auto* v : {&s.n1[dir], &s.n2[dir], &s.q1[dir], &s.q2[dir], &s.cw[dir]}) v->assign(w, 1.f);
  for (auto* v : {&s.open, &s.sum, &s.cnt}) v->resize(w);
  s.e.resize(size_t(n_pred) * w);
  float* cnt = s.cnt.data();
  float* open_at = s.open.data();
  const float min_support = float(std::max(cf.min_support, 1));

  // Per padded row: the columns of its holes (inside the image, not kept), rebuilt each round.
  std::vector<int>& holes = s.holes;
  std::vector<int>& hole_start = s.hole_start;
  for (int it = 1; it <= cf.iterations; ++it) {
    const float tau = static_cast<float>(cf.threshold * it / cf.iterations);
    holes.clear();
    hole_start.assign(size_t(ph) + 1, 0);
    for (int r = 0; r < ph; ++r) {
      hole_start[r] = int(holes.size());
      if (r < pad || r >= pad + h) continue;
      const float* kr = s.kept.data() + size_t(r) * pw;
      for (int x = pad; x < pad + w; ++x)
        if (kr[x] == 0.f) holes.push_back(x);
    }
    hole_start[ph] = int(holes.size());

    for (int v = 0; v < h; ++v) {
      // Row pointers at the first image column; everything below runs over the w image columns.
      const size_t row = size_t(v + pad) * pw + pad;
      const float* q = s.q.data() + row;
      const float* A = s.a.data() + row;
      const float* kept = s.kept.data() + row;
      for (int dir = 0; dir < kDirs; ++dir) {
        const ptrdiff_t o = off[dir];
        float* n1 = s.n1[dir].data();
        float* n2 = s.n2[dir].data();
        float* q1 = s.q1[dir].data();
        float* q2 = s.q2[dir].data();
        float* cw = s.cw[dir].data();
        int open = 0;
        if (ch) open = nearestTwo<true>(kept + o, kept + 2 * o, q + o, q + 2 * o, colourAt(dir, 1) + row,
                                        colourAt(dir, 2) + row, n1, n2, q1, q2, cw, open_at, w);
        else open = nearestTwo<false>(kept + o, kept + 2 * o, q + o, q + 2 * o, nullptr, nullptr, n1, n2, q1, q2, cw,
                                      open_at, w);
        if (open == 0 || reach <= 2) continue;
        // Near holes: search on, pixel by pixel, up to `reach`. An open search has a hole at step 1
        // or 2, so the holes of those rows name the pixels to look at.
        const int du = step_of[dir][0], dv = step_of[dir][1];
        for (int step = 1; step <= 2; ++step) {
          const int r = v + step * dv + pad;
          for (int hk = hole_start[r]; hk < hole_start[r + 1]; ++hk) {
            const int x = holes[hk] - step * du - pad;
            if (x < 0 || x >= w || open_at[x] == 0.f) continue;
            open_at[x] = 0.f;
            for (int n = 3; n <= reach; ++n) {
              const float kn = kept[x + n * o];
              if (kn < 0.f) break;
              if (kn == 0.f) continue;
              if (n1[x] == 0.f) {
                n1[x] = float(n), q1[x] = q[x + n * o];
                if (ch) cw[x] = std::exp(-colourDist2(s.c.data(), ch, row + x, row + x + n * o) * inv_sc);
              } else {
                n2[x] = float(n), q2[x] = q[x + n * o];
                break;
              }
            }
          }
        }
      }
      std::fill_n(cnt, w, 0.f);
      float* e = s.e.data();
      if (slope) {
        for (int dir = 0; dir < kDirs; dir += 2, e += w)  // two-sided: between the nearest on each side
          twoSided(s.n1[dir].data(), s.n1[dir + 1].data(), s.q1[dir].data(), s.q1[dir + 1].data(), q, A,
                   s.cw[dir].data(), e, cnt, w);
        for (int dir = 0; dir < kDirs; ++dir, e += w)  // one-sided: extrapolated from the nearest two
          oneSided(s.n1[dir].data(), s.n2[dir].data(), s.q1[dir].data(), s.q2[dir].data(), q, A, s.cw[dir].data(),
                   e, cnt, w);
      } else {
        for (int dir = 0; dir < kDirs; ++dir, e += w)  // eq. 6.4 as written: the adjacent pixel's own depth
          adjacent(s.n1[dir].data(), s.q1[dir].data(), q, A, s.cw[dir].data(), e, cnt, w);
      }
      cv::Mat em(1, n_pred * w, CV_32F, s.e.data());
      cv::exp(em, em);
      float* sum = s.sum.data();
      std::fill_n(sum, w, 0.f);
      for (int p = 0; p < n_pred; ++p) addRow(s.e.data() + size_t(p) * w, sum, w);
      const float* cand = s.cand.data() + row;
      float* next = s.next.data() + row;
      for (int x = 0; x < w; ++x) {
        const float need = tau * std::max(cnt[x], min_support);
        next[x] = sum[x] >= need ? cand[x] : 0.f;
      }
    }
    s.kept.swap(s.next);
  }
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w; ++u) {
      const size_t p = size_t(v + pad) * pw + u + pad;
      if (s.cand[p] > 0.f && s.kept[p] <= 0.f) work.reject(size_t(v) * w + u, DepthReject::kConfidence);
    }
}

}  // namespace polyloc::depth_detail
