/* libpolyloc_client: the C ABI of polyloc's shared-memory interface, for controllers and drivers
 * in any language with a C FFI. docs/interface.md is the spec; docs/examples/controller.c a
 * complete client.
 *
 *   polyloc_client* c;
 *   if (polyloc_attach("lab", &c) != POLYLOC_OK) { fprintf(stderr, "%s\n", polyloc_last_error()); ... }
 *   int odom = polyloc_channel(c, "odom");
 *   polyloc_write_odometry(c, odom, stamp_ns, pose7, NULL);
 *   polyloc_pose p;
 *   if (polyloc_wait(c, polyloc_channel(c, "pose"), 100000000) == POLYLOC_OK) polyloc_next_pose(c, &p, NULL);
 *   polyloc_detach(c);
 *
 * Every function returns a status: 0 (POLYLOC_OK), a positive note (POLYLOC_NO_DATA,
 * POLYLOC_TIMEOUT) or a negative error; after an error polyloc_last_error() says what was wrong
 * and where (a message per thread). No function blocks except polyloc_wait, none throws, none
 * keeps a pointer the caller passed. A handle is used by one thread at a time; different handles
 * (even on one instance) are independent. */
#ifndef POLYLOC_CLIENT_H
#define POLYLOC_CLIENT_H

#include "polyloc_shm.h"

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#if defined(__GNUC__)
#define POLYLOC_API __attribute__((visibility("default")))
#else
#define POLYLOC_API
#endif

/* Status codes. */
enum {
  POLYLOC_OK = 0,
  POLYLOC_NO_DATA = 1,          /* no frame (yet, or no new one) on the channel */
  POLYLOC_TIMEOUT = 2,          /* polyloc_wait: nothing came within the timeout */
  POLYLOC_ERR_ARGUMENT = -1,    /* a NULL pointer, bad channel index, bad instance name, array too small */
  POLYLOC_ERR_NOT_FOUND = -2,   /* no segment for the instance (polylocd not running), or no such channel */
  POLYLOC_ERR_ABI = -3,         /* the segment speaks another POLYLOC_SHM_ABI_VERSION: update the client */
  POLYLOC_ERR_NOT_READY = -4,   /* polylocd is starting: retry shortly */
  POLYLOC_ERR_BAD_SEGMENT = -5, /* not a polyloc segment, or a corrupt one */
  POLYLOC_ERR_STALE = -6,       /* polylocd stopped or restarted: polyloc_reattach */
  POLYLOC_ERR_BUSY = -7,        /* another live process is the channel's writer */
  POLYLOC_ERR_KIND = -8,        /* the channel's kind or direction does not fit the call */
  POLYLOC_ERR_SIZE = -9,        /* count/width/height not the channel's, or the frame does not fit */
  POLYLOC_ERR_SYSTEM = -10,     /* a system call failed (permissions, memory): see polyloc_last_error */
  POLYLOC_ERR_INTERNAL = -11    /* a bug: please report polyloc_last_error() */
};

typedef struct polyloc_client polyloc_client; /* opaque */

typedef struct {
  uint64_t frame;      /* its number on the channel (0, 1, ...) */
  uint32_t size;       /* payload bytes */
  uint32_t kind;       /* POLYLOC_KIND_* */
  int64_t stamp_ns;    /* the data's time */
  int64_t publish_ns;  /* CLOCK_MONOTONIC when the writer published it */
} polyloc_frame_info;

/* The message of the last failed call in this thread ("" when none). Valid until the next call. */
POLYLOC_API const char* polyloc_last_error(void);
/* The layout version this library speaks (POLYLOC_SHM_ABI_VERSION it was built with). */
POLYLOC_API uint32_t polyloc_abi_version(void);
/* A short name of a status code ("ok", "no data", "timeout", "abi", ...). */
POLYLOC_API const char* polyloc_status_name(int status);
/* The yaw (rad, -pi..pi) of the unit quaternion (qw, qx, qy, qz) of a pose, odometry or
   map_odom: the rotation about z, as tf2::getYaw. */
POLYLOC_API double polyloc_quaternion_yaw(double qw, double qx, double qy, double qz);

/* Maps the segment of instance ("lab" -> /polyloc.lab). *out is set only on success. */
POLYLOC_API int polyloc_attach(const char* instance, polyloc_client** out);
/* Releases writer roles and unmaps. NULL is allowed. */
POLYLOC_API void polyloc_detach(polyloc_client* c);
/* The generation attached (bumped by every polylocd start); 0 for NULL. */
POLYLOC_API uint32_t polyloc_generation(const polyloc_client* c);
/* 1 when polylocd stopped, died or restarted since attaching (re-attach), 0 when not, < 0 error.
 * A few system calls: call it when a wait times out or about once a second. */
POLYLOC_API int polyloc_stale(const polyloc_client* c);
/* Maps the instance's current segment in place of the old one. Channel indices may change with
 * a new configuration: look them up again. On failure the handle keeps the old mapping. */
POLYLOC_API int polyloc_reattach(polyloc_client* c);

/* The index of the named channel ("odom", "scan/front", "pose", ...), or POLYLOC_ERR_NOT_FOUND. */
POLYLOC_API int polyloc_channel(const polyloc_client* c, const char* name);
POLYLOC_API int polyloc_channel_count(const polyloc_client* c);
/* A copy of the channel's descriptor (kind, count, width, height, slot_count, ...). */
POLYLOC_API int polyloc_channel_info(const polyloc_client* c, int channel, polyloc_channel_desc* out);

/* Writing input channels. The first write claims the channel's writer role (POLYLOC_ERR_BUSY
 * while another live process holds it; a dead holder is replaced). stamp_ns: the data's time,
 * CLOCK_REALTIME of the robot. */
POLYLOC_API int polyloc_claim_writer(polyloc_client* c, int channel, int take_over);
/* A scan: count must be the channel's beam count. */
POLYLOC_API int polyloc_write_ranges(polyloc_client* c, int channel, int64_t stamp_ns, const float* ranges,
                                     uint32_t count);
/* A depth frame, row-major; amplitude may be NULL. width/height must be the channel's. */
POLYLOC_API int polyloc_write_depth(polyloc_client* c, int channel, int64_t stamp_ns, const float* depth,
                                    const float* amplitude, uint32_t width, uint32_t height);
/* Odometry: pose = x y z qw qx qy qz (odom_T_base); twist = vx vy wz, or NULL for zeros. */
POLYLOC_API int polyloc_write_odometry(polyloc_client* c, int channel, int64_t stamp_ns, const double pose[7],
                                       const double twist[3]);
/* A controller's velocity command on "cmd_vel" (base_link: vx, vy m/s, wz rad/s), with its mission
 * state (POLYLOC_NAV_*), goal number and a status line (NULL: ""; cut at 63 bytes). A value that is
 * not finite or beyond +-POLYLOC_COMMAND_MAX (100), or a nav_state above POLYLOC_NAV_FAILED: POLYLOC_ERR_ARGUMENT, nothing written. */
POLYLOC_API int polyloc_write_command(polyloc_client* c, int channel, int64_t stamp_ns, double vx, double vy,
                                      double wz, uint32_t nav_state, uint32_t goal, const char* status);

/* Reading output channels. "read" gives the newest frame (again, if nothing newer came);
 * "next" the oldest frame not yet read through this handle (POLYLOC_NO_DATA when none: call
 * polyloc_wait). After an overrun "next" skips to the newest. info may be NULL. */
POLYLOC_API int polyloc_read_pose(polyloc_client* c, polyloc_pose* out, polyloc_frame_info* info);
POLYLOC_API int polyloc_next_pose(polyloc_client* c, polyloc_pose* out, polyloc_frame_info* info);
/* The newest VRS: its fixed part in *out, its ranges in ranges[0..capacity) (*count set to the
 * number of segments; POLYLOC_ERR_SIZE when capacity is less). ranges may be NULL with capacity 0. */
POLYLOC_API int polyloc_read_vrs(polyloc_client* c, polyloc_vrs* out, float* ranges, uint32_t capacity,
                                 uint32_t* count, polyloc_frame_info* info);
POLYLOC_API int polyloc_read_tracks(polyloc_client* c, polyloc_tracks* out, polyloc_frame_info* info);
POLYLOC_API int polyloc_read_health(polyloc_client* c, polyloc_health* out, polyloc_frame_info* info);
/* The newest command on "cmd_vel" (a base driver's or a monitor's read). */
POLYLOC_API int polyloc_read_command(polyloc_client* c, polyloc_command* out, polyloc_frame_info* info);
/* Any channel, raw payload bytes (the payload structs of polyloc_shm.h): newest or next. */
POLYLOC_API int polyloc_read_newest(polyloc_client* c, int channel, void* buf, uint32_t capacity,
                                    polyloc_frame_info* info);
POLYLOC_API int polyloc_read_next(polyloc_client* c, int channel, void* buf, uint32_t capacity,
                                  polyloc_frame_info* info);

/* Sleeps until the channel has a frame this handle has not read ("next"), at most timeout_ns
 * (< 0: no limit, 0: poll). POLYLOC_OK, POLYLOC_TIMEOUT, or POLYLOC_ERR_STALE when it timed
 * out because polylocd is gone. */
POLYLOC_API int polyloc_wait(polyloc_client* c, int channel, int64_t timeout_ns);
/* The same, spinning up to spin_ns before sleeping: a frame that comes within spin_ns is seen
 * in about a microsecond instead of after a thread wake-up (tens of microseconds on a VM), at
 * the cost of a busy CPU meanwhile (docs/interface.md, "Waiting"). */
POLYLOC_API int polyloc_wait_spin(polyloc_client* c, int channel, int64_t timeout_ns, int64_t spin_ns);

#ifdef __cplusplus
}
#endif
#endif /* POLYLOC_CLIENT_H */
