/* A minimal controller on polyloc's C ABI (docs/interface.md): attach to a running polylocd,
 * write one odometry frame and one scan, wait for the pose estimate and print it.
 *
 *   cc -std=c11 -Wall -Werror controller.c -lpolyloc_client -o controller
 *   ./controller lab [scan-channel]         (default: the first scan channel)
 *
 * A real controller runs the write/wait part in its control loop, and calls polyloc_stale()
 * when a wait times out, re-attaching when polylocd has restarted. */
#define _POSIX_C_SOURCE 200809L
#include <polyloc_client.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static int64_t now_ns(void) {
  struct timespec ts;
  clock_gettime(CLOCK_REALTIME, &ts);
  return (int64_t)ts.tv_sec * 1000000000 + ts.tv_nsec;
}

/* Prints what went wrong and returns the exit status. */
static int report(const char* what, int status) {
  fprintf(stderr, "controller: %s: %s (%s)\n", what, polyloc_status_name(status), polyloc_last_error());
  return 1;
}

/* The first input channel of this kind, or -1. */
static int first_input(polyloc_client* c, uint32_t kind) {
  int n = polyloc_channel_count(c);
  for (int i = 0; i < n; ++i) {
    polyloc_channel_desc d;
    if (polyloc_channel_info(c, i, &d) == POLYLOC_OK && d.kind == kind && d.direction == POLYLOC_DIR_INPUT) return i;
  }
  return -1;
}

int main(int argc, char** argv) {
  const char* instance = argc > 1 ? argv[1] : "lab";
  polyloc_client* c = NULL;
  int s = polyloc_attach(instance, &c);
  if (s != POLYLOC_OK) return report("attach", s);
  printf("attached to instance %s, generation %u, ABI %u\n", instance, polyloc_generation(c), polyloc_abi_version());

  int odom = polyloc_channel(c, "odom");
  int scan = argc > 2 ? polyloc_channel(c, argv[2]) : first_input(c, POLYLOC_KIND_RANGES);
  int pose_ch = polyloc_channel(c, "pose");
  if (odom < 0 || scan < 0 || pose_ch < 0) {
    fprintf(stderr, "controller: the segment lacks odom, a scan channel or pose (%s)\n", polyloc_last_error());
    polyloc_detach(c);
    return 1;
  }

  /* Odometry: standing at the odom origin, facing +x. */
  const double pose7[7] = {0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0};
  s = polyloc_write_odometry(c, odom, now_ns(), pose7, NULL);
  if (s != POLYLOC_OK) return report("write odometry", s);

  /* A scan of the channel's beam count: a wall 2 m away all around (a real driver copies its
   * ranges here; NaN for beams without a return). */
  polyloc_channel_desc d;
  polyloc_channel_info(c, scan, &d);
  float* ranges = malloc(sizeof(float) * (d.count ? d.count : 1));
  if (!ranges) return 1;
  for (uint32_t i = 0; i < d.count; ++i) ranges[i] = 2.0f;
  s = polyloc_write_ranges(c, scan, now_ns(), ranges, d.count);
  free(ranges);
  if (s != POLYLOC_OK) return report("write scan", s);
  printf("wrote odometry and a scan of %u beams on %s\n", d.count, d.name);

  /* Wait up to 2 s for the pose published after the scan. */
  polyloc_pose p;
  polyloc_frame_info info;
  s = polyloc_wait(c, pose_ch, 2000000000LL);
  if (s != POLYLOC_OK) return report("wait for the pose", s);
  s = polyloc_next_pose(c, &p, &info);
  if (s != POLYLOC_OK) return report("read the pose", s);
  const double yaw = atan2(2.0 * (p.qw * p.qz + p.qx * p.qy), 1.0 - 2.0 * (p.qy * p.qy + p.qz * p.qz));
  printf("pose frame %llu: x %.3f y %.3f yaw %.3f status %u ess %.1f latency %.3f ms\n",
         (unsigned long long)info.frame, p.x, p.y, yaw, p.status, p.ess, p.latency_ns * 1e-6);
  polyloc_detach(c);
  return 0;
}
