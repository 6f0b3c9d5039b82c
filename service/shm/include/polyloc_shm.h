/* polyloc shared-memory interface: the layout of one polylocd instance's segment, in C.
 * docs/interface.md is the spec; this header is its code form and the only definition of the
 * structs (polylocd, libpolyloc_client and the Python module all include it).
 *
 * One POSIX shared-memory object per instance ("/polyloc.<instance>", shm_open), laid out as
 *   [polyloc_shm_header][ring 0][ring 1]...      every ring 64-byte aligned
 *   ring = [polyloc_ring_control][slot 0]...[slot N-1], slot = [polyloc_slot_header][payload]
 * Little-endian, fixed-size structs, no pointers. Each channel has one writer: input channels
 * (sensors, odometry) are written by a client, output channels (pose, VRS, tracks, health) by
 * polylocd. Frame n of a channel goes to slot n % slot_count. Its writer sets the slot's seq to
 * 2n+1, writes header fields and payload, sets seq to 2n+2 (release), then publishes:
 * write_count = n+1, notify += 1 and FUTEX_WAKE on notify. A reader wanting frame n reads seq
 * (acquire); 2n+2 means complete; it reads the payload in place and re-reads seq: unchanged means
 * what it read is frame n, untorn. Input writers also bump the header's doorbell, so polylocd waits
 * on one word for all its inputs. write_count - n > slot_count means frame n was overwritten
 * (overrun): the reader skips to the newest. A writer killed mid-frame leaves one odd seq: that
 * frame never becomes visible, and the next writer overwrites the slot. */
#ifndef POLYLOC_SHM_H
#define POLYLOC_SHM_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define POLYLOC_SHM_MAGIC 0x4d48534c4f4c4f50ull /* "POLOLSHM" little-endian */
#define POLYLOC_SHM_ABI_VERSION 2u
#define POLYLOC_MAX_CHANNELS 32u
#define POLYLOC_NAME_LEN 32u
#define POLYLOC_MAX_TRACKS 64u
#define POLYLOC_MAX_INPUTS 24u  /* health entries: one per input channel */

/* Segment states (polyloc_shm_header.state). */
enum { POLYLOC_STATE_INITIALISING = 0, POLYLOC_STATE_READY = 1, POLYLOC_STATE_STOPPED = 2 };

/* Channel kinds: what a slot's payload is. */
enum {
  POLYLOC_KIND_RANGES = 1,   /* polyloc_ranges: a scanner's or lidar's ranges in the rig's beam order */
  POLYLOC_KIND_DEPTH = 2,    /* polyloc_depth: depth (+ amplitude) image of a ToF/PMD camera */
  POLYLOC_KIND_ODOMETRY = 3, /* polyloc_odometry */
  POLYLOC_KIND_COMMAND = 4,  /* polyloc_command: a controller's velocity command, for the base (polylocd hosts it) */
  POLYLOC_KIND_POSE = 10,    /* polyloc_pose */
  POLYLOC_KIND_VRS = 11,     /* polyloc_vrs */
  POLYLOC_KIND_TRACKS = 12,  /* polyloc_tracks */
  POLYLOC_KIND_HEALTH = 13   /* polyloc_health */
};
enum { POLYLOC_DIR_INPUT = 0, POLYLOC_DIR_OUTPUT = 1 };

typedef struct {
  char name[POLYLOC_NAME_LEN]; /* "scan/<sensor>", "depth/<sensor>", "odom", "cmd_vel", "pose", "vrs", "tracks", "health" */
  uint32_t kind;               /* POLYLOC_KIND_* */
  uint32_t direction;          /* POLYLOC_DIR_* */
  uint32_t slot_count;         /* power of two */
  uint32_t slot_size;          /* bytes: slot header + payload capacity, multiple of 64 */
  uint64_t offset;             /* of the ring (polyloc_ring_control) from the segment start */
  uint32_t payload_max;        /* bytes a payload may hold (slot_size - sizeof(polyloc_slot_header)) */
  int32_t sensor;              /* rig index of an input sensor, -1 otherwise */
  uint32_t count;              /* RANGES: beams per frame; DEPTH: width*height; VRS: segments; else 0 */
  uint32_t width, height;      /* DEPTH: image size; else 0 */
  uint8_t reserved[20];
} polyloc_channel_desc;        /* 96 bytes */

typedef struct {
  uint64_t magic;              /* POLYLOC_SHM_MAGIC, written last when the segment is ready */
  uint32_t abi_version;        /* POLYLOC_SHM_ABI_VERSION */
  uint32_t header_size;        /* sizeof(polyloc_shm_header) */
  uint64_t total_size;         /* bytes of the whole segment */
  uint32_t generation;         /* bumped by every polylocd start on this name: re-attach when it changes */
  uint32_t state;              /* POLYLOC_STATE_* */
  int32_t owner_pid;           /* polylocd's pid */
  uint32_t channel_count;
  int64_t created_ns;          /* CLOCK_REALTIME of the start */
  char instance[POLYLOC_NAME_LEN];
  uint32_t doorbell;           /* futex word: +1 (and FUTEX_WAKE) whenever any input channel publishes */
  uint8_t reserved[20];
  polyloc_channel_desc channels[POLYLOC_MAX_CHANNELS];
} polyloc_shm_header;

typedef struct {
  uint64_t write_count;        /* frames published; frame n is complete once write_count > n */
  uint32_t notify;             /* futex word: +1 per frame published; waiters FUTEX_WAIT on it */
  int32_t writer_pid;          /* input channels: the client that claimed the writer role (0: none) */
  uint64_t writer_claims;      /* times a writer took the channel over */
  uint8_t reserved[40];
} polyloc_ring_control;        /* 64 bytes */

typedef struct {
  uint64_t seq;                /* 2n+1 while frame n is being written, 2n+2 when it is complete */
  uint32_t size;               /* payload bytes */
  uint32_t kind;               /* POLYLOC_KIND_* (= the channel's) */
  int64_t stamp_ns;            /* the data's time (sensor clock = CLOCK_REALTIME of the robot) */
  int64_t publish_ns;          /* CLOCK_MONOTONIC when it was published: latency, and polylocd's order of
                                  frames with one stamp (a writer of its own must set it so) */
  uint8_t reserved[32];
} polyloc_slot_header;         /* 64 bytes */

/* Payloads. Variable arrays follow the fixed part; size = offsetof(array) + count * element. */
typedef struct {
  int64_t stamp_ns;
  uint32_t count;              /* = the channel's count */
  uint32_t reserved;
  float ranges[];              /* metres; NaN/inf/out of range: no return */
} polyloc_ranges;

typedef struct {
  int64_t stamp_ns;
  uint32_t width, height;      /* = the channel's */
  uint32_t has_amplitude;      /* 1: amplitude[] follows depth[] */
  uint32_t reserved;
  float data[];                /* depth (metres along the optical axis), row-major; then amplitude */
} polyloc_depth;

typedef struct {
  int64_t stamp_ns;
  double x, y, z;              /* odom_T_base, cumulative, as nav_msgs/Odometry */
  double qw, qx, qy, qz;
  double vx, vy, wz;           /* base frame twist (informational) */
} polyloc_odometry;

/* A controller's velocity command for the base (geometry_msgs/Twist in base_link) and what the
 * controller is doing. polylocd only hosts the channel ("cmd_vel", an input it never reads); the
 * base driver (or `polyloc play --drive`) reads the newest frame and stops the robot when none came
 * for its command timeout (0.5 s), as a real base does. */
enum { POLYLOC_NAV_IDLE = 0, POLYLOC_NAV_DRIVING = 1, POLYLOC_NAV_REACHED = 2, POLYLOC_NAV_FAILED = 3 };
/* |vx|, |vy|, |wz| beyond this (m/s, rad/s) is no command a base could execute: refused, not clamped */
#define POLYLOC_COMMAND_MAX 100.0
typedef struct {
  int64_t stamp_ns;            /* the data's time the command answers (the stamp of the pose/VRS it used) */
  double vx, vy, wz;           /* base_link: m/s forward, m/s left (0 on a differential base), rad/s */
  uint32_t nav_state;          /* POLYLOC_NAV_*: the controller's mission state */
  uint32_t goal;               /* the goal it works on (the controller's numbering) */
  char status[64];             /* one short line ("lab 1: door passage"), NUL-terminated */
} polyloc_command;             /* 104 bytes */

enum { POLYLOC_POSE_INITIALISING = 0, POLYLOC_POSE_TRACKING = 1, POLYLOC_POSE_UNCERTAIN = 2, POLYLOC_POSE_LOST = 3 };
typedef struct {
  int64_t stamp_ns;            /* of the scan that ended the update */
  double x, y, z;              /* map_T_base */
  double qw, qx, qy, qz;
  double covariance[36];       /* x y z roll pitch yaw, row-major */
  double map_odom[7];          /* map_T_odom correction (x y z qw qx qy qz), REP-105 */
  uint32_t status;             /* POLYLOC_POSE_* */
  uint32_t particles;
  double ess;
  uint64_t updates;
  int64_t latency_ns;          /* from the input frame's publish to this pose's publish */
} polyloc_pose;

typedef struct {
  int64_t stamp_ns;
  float angle_min, angle_increment, range_min, range_max; /* base_link, like sensor_msgs/LaserScan */
  uint32_t count;
  uint32_t enabled;            /* 0 when collision avoidance publication is switched off */
  float ranges[];              /* range_max + 1: nothing in this segment */
} polyloc_vrs;

typedef struct {
  uint32_t id, status;         /* status: 0 tentative, 1 confirmed */
  double x, y, vx, vy;         /* map frame */
  double covariance[4];        /* position, row-major 2x2 */
} polyloc_track;
typedef struct {
  int64_t stamp_ns;
  uint32_t count, reserved;
  polyloc_track tracks[POLYLOC_MAX_TRACKS];
} polyloc_tracks;

typedef struct {
  uint64_t taken;              /* frames used */
  uint64_t rejected_nan;       /* a value outside its domain: NaN/inf, odometry beyond 1e6 m, no range a distance (docs/failure.md) */
  uint64_t rejected_size;      /* size or count not the channel's */
  uint64_t rejected_stale;     /* stamp older than the last or than now - max_age */
  uint64_t rejected_future;    /* stamp later than now + max_future */
  uint64_t overruns;           /* frames overwritten before polylocd read them */
  int64_t last_stamp_ns;       /* of the last frame taken */
  uint32_t silent;             /* 1: no frame for longer than the input timeout */
  uint32_t map_fit_permille;   /* share of this sensor's beams the map explains at the estimate, smoothed
                                  (mcl.fit), in 1/1000, at least 1; 0: not measured (odometry, not weighed) */
  uint64_t extrapolated;       /* frames weighed with the motion extrapolated past the newest odometry
                                  (it did not come within polylocd.odom_wait, or it is silent) */
} polyloc_input_health;
typedef struct {
  int64_t stamp_ns;            /* CLOCK_REALTIME when written */
  uint64_t cycles;             /* pipeline cycles */
  uint64_t poses, vrs, tracks; /* outputs published */
  double cycle_p50_ms, cycle_p99_ms;  /* over the last 1000 cycles */
  uint32_t inputs;             /* entries in input[] (= input channels, in channel order) */
  uint32_t flags;              /* bit 0: some input silent; bit 1: localisation lost; bit 2: the scans do not fit the map;
                                  bit 3: a global search runs */
  polyloc_input_health input[POLYLOC_MAX_INPUTS];
} polyloc_health;

#ifdef __cplusplus
}
#endif
#endif /* POLYLOC_SHM_H */
