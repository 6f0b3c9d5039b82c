#!/usr/bin/python3
"""Peer for 6-DoF depth-camera tracking: frame-to-mesh point-to-plane ICP with Open3D.

The tool a user would reach for instead of polyloc: each depth frame, back-projected to a
cloud, is registered to a fixed mesh with Open3D's registration_icp (point-to-plane),
initialised at the previous frame's estimate, and scored against the recording's ground truth.

  /usr/bin/python3 bench/peer_open3d_icp.py --input DIR --map MESH.ply [--frames odd]
      [--decimate N] [--start-offset M,DEG] [--kidnap FRAME,M,DEG] [--pixels N]
      [--max-correspondence M] [--iterations N] [--json]

Needs Debian's python3-open3d (0.16) for /usr/bin/python3; exits 0 with a note without it.

Choices:
- Input: 7-Scenes layout (frame-NNNNNN.depth.png in mm, 0/65535 invalid, frame-NNNNNN.pose.txt
  camera-to-world of the optical frame, camera-intrinsics.txt) or TUM RGB-D (depth.txt,
  groundtruth.txt interpolated to depth stamps within 50 ms, 5000 units/m, fx=fy=525,
  cx=319.5, cy=239.5 unless intrinsics.yaml gives fx, fy, cx, cy, depth_scale).
  TUM frames without ground truth are dropped.
- Frame indices (--frames, --kidnap FRAME) are indices of the recording (7-Scenes frame number,
  TUM line of depth.txt), not positions in the selected subsequence.
- Source cloud: --pixels valid pixels drawn without replacement by a RNG seeded with the frame
  index (deterministic, no grid aliasing), back-projected with K.
- Target: the mesh's vertices with vertex normals (computed once). A TSDF mesh's vertices are
  already a dense, even sampling of the surface, so no extra sampling is done.
- ICP: max correspondence distance 0.10 m (--max-correspondence), at most 30 iterations,
  relative fitness / RMSE 1e-6. No robust kernel: the plain call a user would write.
- Start: the first frame's ground truth displaced by --start-offset: M metres along the world
  direction (1,1,1)/sqrt(3) and DEG degrees about the camera's own optical y axis (a pan about
  its centre). --kidnap applies the same displacement to the previous estimate at FRAME.
- Scoring: translation error |t_est - t_gt| (no trajectory alignment: the mesh and the poses share
  the world frame) and rotation error = angle of R_gt^T R_est. A frame is lost when its error
  exceeds 0.10 m or 5 deg. "Recovered" after a kidnap = first frame from FRAME on with < 5 cm.
- Frame counts after a kidnap or start offset are selected frames (x2 recording frames on odd).
- Timing: the fps is the ICP calls' wall time only; PNG reading and back-projection are timed
  apart (load_s).
"""
import argparse
import json
import math
import os
import sys
import time

try:  # numpy too: the python3 first on PATH may lack both
    import numpy as np
    import open3d as o3d
except ImportError:
    print("peer_open3d_icp: open3d is not installed (Debian python3-open3d, for /usr/bin/python3); skipped")
    sys.exit(0)

LOST_M, LOST_DEG = 0.10, 5.0
GOOD_M, GOOD_DEG = 0.05, 2.0
OFFSET_DIR = np.ones(3) / math.sqrt(3.0)


def quat_to_R(q):
    x, y, z, w = q / np.linalg.norm(q)
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def slerp(q0, q1, a):
    d = float(np.dot(q0, q1))
    if d < 0:  # shortest arc
        q1, d = -q1, -d
    if d > 0.9995:
        q = q0 + a * (q1 - q0)
    else:
        th = math.acos(d)
        q = (math.sin((1 - a) * th) * q0 + math.sin(a * th) * q1) / math.sin(th)
    return q / np.linalg.norm(q)


def orthonormal(T):
    """Nearest rotation (SVD). 7-Scenes' stored blocks are off by ~5e-4, which alone would read
    as ~1.3 deg through acos((tr - 1) / 2) near zero."""
    u, _, vt = np.linalg.svd(T[:3, :3])
    out = T.copy()
    out[:3, :3] = u @ np.diag([1.0, 1.0, np.linalg.det(u @ vt)]) @ vt
    return out


def load_recording(d):
    """-> (K, depth_scale, [(index, png_path, 4x4 camera-to-world)]) for 7-Scenes or TUM."""
    if os.path.exists(os.path.join(d, "camera-intrinsics.txt")):
        K = np.loadtxt(os.path.join(d, "camera-intrinsics.txt"))
        frames, i = [], 0
        while os.path.exists(os.path.join(d, "frame-%06d.depth.png" % i)):
            frames.append((i, os.path.join(d, "frame-%06d.depth.png" % i),
                           orthonormal(np.loadtxt(os.path.join(d, "frame-%06d.pose.txt" % i)))))
            i += 1
        return K, 1000.0, frames
    if not os.path.exists(os.path.join(d, "depth.txt")):
        sys.exit("peer_open3d_icp: %s is neither 7-Scenes nor TUM RGB-D" % d)
    cal = {"fx": 525.0, "fy": 525.0, "cx": 319.5, "cy": 239.5, "depth_scale": 5000.0}
    yml = os.path.join(d, "intrinsics.yaml")
    if os.path.exists(yml):
        for line in open(yml):
            k, _, v = line.partition(":")
            if k.strip() in cal and v.strip():
                cal[k.strip()] = float(v.split("#")[0])
    K = np.array([[cal["fx"], 0, cal["cx"]], [0, cal["fy"], cal["cy"]], [0, 0, 1.0]])
    rows = lambda f: [l.split() for l in open(os.path.join(d, f)) if l.strip() and l[0] != "#"]
    gt = np.array([[float(x) for x in r[:8]] for r in rows("groundtruth.txt")])
    frames = []
    for i, (t, name) in enumerate((float(r[0]), r[1]) for r in rows("depth.txt")):
        j = np.searchsorted(gt[:, 0], t)
        if j == 0 or j == len(gt) or t - gt[j - 1, 0] > 0.05 or gt[j, 0] - t > 0.05:
            continue
        a = (t - gt[j - 1, 0]) / (gt[j, 0] - gt[j - 1, 0])
        T = np.eye(4)
        T[:3, 3] = (1 - a) * gt[j - 1, 1:4] + a * gt[j, 1:4]
        T[:3, :3] = quat_to_R(slerp(gt[j - 1, 4:8], gt[j, 4:8], a))
        frames.append((i, os.path.join(d, name), T))
    return K, cal["depth_scale"], frames


def select(frames, spec, decimate):
    if spec in ("odd", "even", "all"):
        keep = {"odd": lambda i: i % 2 == 1, "even": lambda i: i % 2 == 0, "all": lambda i: True}[spec]
        sel = [f for f in frames if keep(f[0])]
    else:
        p = [int(x) for x in spec.split(":")]
        first, last, step = p[0], p[1], (p[2] if len(p) > 2 else 1)
        sel = [f for f in frames if first <= f[0] <= last and (f[0] - first) % step == 0]
    return sel[::decimate]


def cloud_of(png, index, K, scale, npix):
    """Depth PNG -> npix back-projected points in the optical frame (x right, y down, z forward)."""
    z = np.asarray(o3d.io.read_image(png)).astype(np.float64)
    v, u = np.nonzero((z > 0) & (z < 65535))
    if len(u) > npix:
        pick = np.random.default_rng(index).choice(len(u), npix, replace=False)
        v, u = v[pick], u[pick]
    z = z[v, u] / scale
    pts = np.stack([(u - K[0, 2]) * z / K[0, 0], (v - K[1, 2]) * z / K[1, 1], z], axis=1)
    return o3d.geometry.PointCloud(o3d.utility.Vector3dVector(pts))


def displaced(T, metres, deg):
    """T moved `metres` along OFFSET_DIR (world) and panned `deg` about its own optical y axis."""
    out = T.copy()
    out[:3, 3] += metres * OFFSET_DIR
    out[:3, :3] = T[:3, :3] @ o3d.geometry.get_rotation_matrix_from_axis_angle(
        np.array([0.0, math.radians(deg), 0.0]))
    return out


def errors(T_est, T_gt):
    dt = float(np.linalg.norm(T_est[:3, 3] - T_gt[:3, 3]))
    R = T_gt[:3, :3].T @ T_est[:3, :3]
    # atan2 of (|axis part|, cos part): well conditioned at small angles, unlike acos alone
    s = np.linalg.norm([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]]) / 2.0
    return dt, math.degrees(math.atan2(s, (np.trace(R) - 1.0) / 2.0))


def pair(s):
    m, d = s.split(",")
    return float(m), float(d)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--input", required=True)
    ap.add_argument("--map", required=True, help="mesh (.ply) in the poses' world frame")
    ap.add_argument("--frames", default="odd", help="odd|even|all|FIRST:LAST[:STEP] (recording indices)")
    ap.add_argument("--decimate", type=int, default=1)
    ap.add_argument("--start-offset", type=pair, default=(0.0, 0.0), metavar="M,DEG")
    ap.add_argument("--kidnap", default=None, metavar="FRAME,M,DEG")
    ap.add_argument("--pixels", type=int, default=5000)
    ap.add_argument("--max-correspondence", type=float, default=0.10)
    ap.add_argument("--iterations", type=int, default=30)
    ap.add_argument("--json", action="store_true")
    a = ap.parse_args()
    kid = None
    if a.kidnap:
        f, m, d = a.kidnap.split(",")
        kid = (int(f), float(m), float(d))

    K, scale, frames = load_recording(a.input)
    frames = select(frames, a.frames, max(1, a.decimate))
    if not frames:
        sys.exit("peer_open3d_icp: no frames selected")
    if kid and kid[0] not in [f[0] for f in frames]:
        sys.exit("peer_open3d_icp: kidnap frame %d is not among the selected frames" % kid[0])

    mesh = o3d.io.read_triangle_mesh(a.map)
    if len(mesh.triangles):
        mesh.compute_vertex_normals()
        target = o3d.geometry.PointCloud(mesh.vertices)
        target.normals = mesh.vertex_normals
    else:  # a bare point cloud: estimate normals instead
        target = o3d.io.read_point_cloud(a.map)
        target.estimate_normals(o3d.geometry.KDTreeSearchParamHybrid(radius=0.05, max_nn=30))
    # Open3D rebuilds the target's KD-tree inside every registration_icp call (~50 ms for 166k
    # points on this box); the Python API takes no prebuilt tree, so that cost is in the fps.
    est = o3d.pipelines.registration.TransformationEstimationPointToPlane()
    crit = o3d.pipelines.registration.ICPConvergenceCriteria(1e-6, 1e-6, a.iterations)

    T = displaced(frames[0][2], *a.start_offset)
    rows, load_s, icp_s = [], 0.0, 0.0
    for n, (idx, png, T_gt) in enumerate(frames):
        t0 = time.perf_counter()
        src = cloud_of(png, idx, K, scale, a.pixels)
        t1 = time.perf_counter()
        if kid and idx == kid[0]:
            T = displaced(T, kid[1], kid[2])
        r = o3d.pipelines.registration.registration_icp(
            src, target, a.max_correspondence, T, est, crit)
        icp_s += time.perf_counter() - t1
        load_s += t1 - t0
        T = orthonormal(np.asarray(r.transformation))  # keep round-off from piling up
        dt, dr = errors(T, T_gt)
        rows.append((idx, dt, dr, r.fitness))
        if (n + 1) % 50 == 0 or n + 1 == len(frames):
            print("frame %d (%d/%d): err %.1f cm %.2f deg, fitness %.2f, %.1f fps" % (
                idx, n + 1, len(frames), 100 * dt, dr, r.fitness, (n + 1) / icp_s), file=sys.stderr)

    et = np.array([r[1] for r in rows])
    er = np.array([r[2] for r in rows])
    lost = (et > LOST_M) | (er > LOST_DEG)
    res = {
        "peer": "open3d %s registration_icp point-to-plane, frame-to-mesh" % o3d.__version__,
        "input": a.input, "map": a.map, "map_points": len(target.points),
        "frames_spec": a.frames, "decimate": a.decimate, "frames": len(rows),
        "pixels": a.pixels, "max_correspondence_m": a.max_correspondence, "max_iterations": a.iterations,
        "start_offset": list(a.start_offset), "kidnap": list(kid) if kid else None,
        "ate_rmse_cm": 100 * float(np.sqrt(np.mean(et ** 2))),
        "ate_median_cm": 100 * float(np.median(et)),
        "ate_p95_cm": 100 * float(np.percentile(et, 95)),
        "ate_max_cm": 100 * float(et.max()),
        "rot_rmse_deg": float(np.sqrt(np.mean(er ** 2))),
        "within_5cm_2deg": float(np.mean((et < GOOD_M) & (er < GOOD_DEG))),
        "lost_rule": "translation error > %.2f m or rotation error > %.0f deg" % (LOST_M, LOST_DEG),
        "frames_lost": int(lost.sum()),
        "first_lost_frame": int(rows[int(np.argmax(lost))][0]) if lost.any() else None,
        "first_under_5cm_frame": int(rows[int(np.argmax(et < GOOD_M))][0]) if (et < GOOD_M).any() else None,
        "first_under_5cm_after": int(np.argmax(et < GOOD_M)) if (et < GOOD_M).any() else None,
        "mean_fitness": float(np.mean([r[3] for r in rows])),
        "icp_s": icp_s, "load_s": load_s, "fps_icp": len(rows) / icp_s,
    }
    if kid:
        k0 = [r[0] for r in rows].index(kid[0])
        back = next((n for n in range(k0, len(rows)) if et[n] < GOOD_M), None)
        res["kidnap_recovered"] = back is not None
        res["kidnap_frames_to_recover"] = None if back is None else back - k0
        res["kidnap_recovered_at_frame"] = None if back is None else rows[back][0]
        res["frames_lost_after_kidnap"] = int(lost[k0:].sum())
    if a.json:
        print(json.dumps(res))
        return
    print("Open3D %s point-to-plane ICP, frame-to-mesh (%d map points)" % (o3d.__version__, res["map_points"]))
    print("frames: %d (%s, decimate %d), %d px/frame, max corr %.2f m, <= %d iterations" % (
        len(rows), a.frames, a.decimate, a.pixels, a.max_correspondence, a.iterations))
    print("ATE: RMSE %.2f cm, median %.2f cm, p95 %.2f cm, max %.1f cm; rotation RMSE %.2f deg" % (
        res["ate_rmse_cm"], res["ate_median_cm"], res["ate_p95_cm"], res["ate_max_cm"], res["rot_rmse_deg"]))
    print("within 5 cm & 2 deg: %.1f %%" % (100 * res["within_5cm_2deg"]))
    print("lost (%s): %d frames%s" % (res["lost_rule"], res["frames_lost"],
          ", first at frame %d" % res["first_lost_frame"] if lost.any() else ""))
    if a.start_offset != (0.0, 0.0):
        print("start offset %.2f m, %.1f deg: first under 5 cm at frame %s (after %s frames)" % (
            a.start_offset[0], a.start_offset[1], res["first_under_5cm_frame"], res["first_under_5cm_after"]))
    if kid:
        print("kidnap at frame %d (%.2f m, %.1f deg): %s; %d frames lost from there" % (
            kid[0], kid[1], kid[2], "back under 5 cm after %d frames (frame %d)" % (
                res["kidnap_frames_to_recover"], res["kidnap_recovered_at_frame"])
            if back is not None else "never back under 5 cm", res["frames_lost_after_kidnap"]))
    print("ICP %.1f fps (%.1f s ICP, %.1f s loading PNGs + back-projection)" % (
        res["fps_icp"], icp_s, load_s))


if __name__ == "__main__":
    main()
