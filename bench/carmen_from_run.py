#!/usr/bin/python3
"""A polyloc run (MCAP with /ground_truth) as a corrected CARMEN log: one ROBOTLASER1 line per
scan of the chosen scanners, with the laser pose taken from ground truth (what a SLAM-corrected
log holds), and ODOM lines from /odom. Used by bench/carmen_roundtrip.sh.

usage: carmen_from_run.py RUN.mcap OUT.log SENSOR:X:Y:YAW_DEG [SENSOR:X:Y:YAW_DEG ...]
"""
import bisect
import math
import sys

import polyloc


def main():
    run, out, specs = sys.argv[1], sys.argv[2], sys.argv[3:]
    mounts = {}
    for s in specs:
        name, x, y, yaw = s.split(":")
        mounts["/scan/" + name] = (float(x), float(y), math.radians(float(yaw)))
    gt_t, gt = [], []
    for _, _, m in polyloc.open_recording(run, topics=["/ground_truth"]):
        gt_t.append(m["stamp_ns"])
        gt.append((m["pose"].x, m["pose"].y, m["pose"].yaw))
    if not gt:
        sys.exit(f"{run}: no /ground_truth poses")
    lines = scans = 0
    with open(out, "w") as f:
        f.write(f"# CARMEN log from {run}: ROBOTLASER1 laser poses from /ground_truth\n")
        for topic, _, m in polyloc.open_recording(run, topics=["/odom"] + list(mounts)):
            t = m["stamp_ns"]
            ts = f"{t // 1_000_000_000}.{t % 1_000_000_000:09d}"
            if topic == "/odom":
                p = m["pose"]
                f.write(f"ODOM {p.x:.6f} {p.y:.6f} {p.yaw:.6f} 0 0 0 {ts} sim {ts}\n")
                lines += 1
                continue
            k = min(max(bisect.bisect_left(gt_t, t), 1), len(gt) - 1)  # interpolate between k-1 and k
            t0, t1 = gt_t[k - 1], gt_t[k]
            a = 0.0 if t1 == t0 else min(max((t - t0) / (t1 - t0), 0.0), 1.0)
            (x0, y0, w0), (x1, y1, w1) = gt[k - 1], gt[k]
            dw = math.atan2(math.sin(w1 - w0), math.cos(w1 - w0))
            x, y, w = x0 + a * (x1 - x0), y0 + a * (y1 - y0), w0 + a * dw
            mx, my, mw = mounts[topic]
            lx, ly, lw = x + mx * math.cos(w) - my * math.sin(w), y + mx * math.sin(w) + my * math.cos(w), w + mw
            r = m["ranges"]
            fov = m["angle_increment"] * (len(r) - 1)
            # No return: the maximum range, as CARMEN loggers write it (clears free space, marks no hit).
            rs = " ".join(f"{m['range_max']:.3f}" if math.isinf(v) else "0" if math.isnan(v) else f"{v:.3f}" for v in r)
            f.write(f"ROBOTLASER1 0 {m['angle_min']:.6f} {fov:.6f} {m['angle_increment']:.6f} {m['range_max']:.2f} "
                    f"0.01 0 {len(r)} {rs} 0 {lx:.6f} {ly:.6f} {lw:.6f} {x:.6f} {y:.6f} {w:.6f} 0 0 0 0 0 {ts} sim {ts}\n")
            lines += 1
            scans += 1
    print(f"{out}: {lines} lines, {scans} scans", file=sys.stderr)


if __name__ == "__main__":
    main()
