#!/usr/bin/python3
"""MRPT's pf-localization beside polyloc on one case of `polyloc eval carmen --save DIR`.
Used by bench/peer_mrpt.sh (which runs the MRPT tools between the two steps).

  peer_mrpt.py convert DIR STYLE DRIFT DECIMATE OUT [SECTION.KEY=VALUE ...]
      DIR/CASE.mcap + DIR/<style>/map.yaml -> OUT/run.log (CARMEN, one ROBOTLASER1 line per
      scan, drift odometry), OUT/map.yaml + map.pgm (for ros-map-yaml2mrpt), OUT/pf.ini (the
      shipped obs-only config with our overrides), OUT/case.json (shift, stamps, truth).
  peer_mrpt.py score DIR STYLE DRIFT DECIMATE OUT MRPT_STDOUT
      MRPT's per-step mean and polyloc's estimates (DIR/CASE.csv) on the same frames against
      the same truth: one JSON line.

CASE is the saved stem, "STYLE/DRIFT/xN" with "/" as "_" (endpoint_mid_x1).
Needs PYTHONPATH=<build>/python (the polyloc module).
"""
import bisect
import json
import math
import os
import re
import shutil
import sys

import numpy as np
import polyloc

SHIPPED_INI = "/usr/share/mrpt/config_files/pf-localization/localization_demo_obsonly_rawlog.ini"
PARTICLES = 3000
INIT_SIGMA_XY, INIT_SIGMA_YAW_DEG = 0.1, 5.0  # polyloc's start spread (first truth pose)


def read_yaml_map(path):
    """The few keys of a map_server YAML (flat, one key a line), without a YAML library."""
    d = {}
    for line in open(path):
        if ":" in line and not line.lstrip().startswith("#"):
            k, v = line.split(":", 1)
            d[k.strip()] = v.strip()
    origin = [float(x) for x in d["origin"].strip("[]").split(",")]
    return d["image"], float(d["resolution"]), origin


def read_case(mcap):
    """/odom (x, y, yaw by stamp), the scans in order, /ground_truth by stamp."""
    odom_t, odom, scans, truth = [], [], [], {}
    for topic, _, m in polyloc.open_recording(mcap):
        if topic == "/odom":
            odom_t.append(m["stamp_ns"])
            odom.append((m["pose"].x, m["pose"].y, m["pose"].yaw))
        elif topic == "/ground_truth":
            truth[m["stamp_ns"]] = (m["pose"].x, m["pose"].y, m["pose"].yaw)
        elif m.get("type", "").endswith("LaserScan"):
            scans.append(m)
    order = np.argsort(odom_t, kind="stable")
    return [odom_t[i] for i in order], [odom[i] for i in order], scans, truth


def odom_at(odom_t, odom, t):
    """The drift odometry of the scan: /odom at its stamp (eval carmen writes one per log scan)."""
    k = bisect.bisect_right(odom_t, t) - 1
    if k < 0:
        sys.exit(f"no /odom at or before scan stamp {t}")
    return odom[k]


def carmen_stamp(t):
    return f"{t // 1_000_000_000}.{t % 1_000_000_000:09d}"


def robotlaser_line(m, pose):
    """ROBOTLASER1 keeps the field of view (FLASER makes MRPT assume 0.5 deg a beam). MRPT ignores
    the start angle: it spreads the beams symmetrically over +-fov/2 around the sensor's x axis
    (fov/(n-1) apart), so an asymmetric scan (CARMEN's 180 beams: -90 .. +89 deg) is centred by
    turning the laser pose by the scan's middle angle. The laser is at base_link (eval carmen)."""
    r, n = m["ranges"], len(m["ranges"])
    inc, rmin, rmax = m["angle_increment"], m["range_min"], m["range_max"]
    fov = inc * (n - 1)
    mid = m["angle_min"] + fov / 2
    # polyloc: a beam counts when finite and range_min <= r < range_max; MRPT: when 0 < r < maxRange.
    rs = " ".join(f"{rmax:.3f}" if not math.isfinite(v) or v >= rmax else "0" if v < rmin else f"{v:.3f}" for v in r)
    x, y, th = pose
    ts = carmen_stamp(m["stamp_ns"])
    return (f"ROBOTLASER1 0 {-fov / 2:.9f} {fov:.9f} {inc:.9f} {rmax:.3f} 0.01 0 {n} {rs} 0 "
            f"{x:.9f} {y:.9f} {th + mid:.9f} {x:.9f} {y:.9f} {th:.9f} 0 0 0 0 0 {ts} polyloc {ts}\n")


def set_ini(text, section, key, value):
    """Replace key in [section] of an INI text, or add it at the section's start."""
    lines, sec, done = text.split("\n"), None, False
    for i, line in enumerate(lines):
        s = line.strip()
        if s.startswith("["):
            sec = s.strip("[]")
        elif sec == section and re.match(rf"{re.escape(key)}\s*=", s):
            lines[i], done = f"{key}={value}", True
    if not done:
        i = next((i for i, l in enumerate(lines) if l.strip() == f"[{section}]"), None)
        if i is None:
            lines += [f"[{section}]", f"{key}={value}"]
        else:
            lines.insert(i + 1, f"{key}={value}")
    return "\n".join(lines)


def stem(style, drift, dec):
    return f"{style}/{drift}/x{dec}".replace("/", "_")  # as eval carmen --save names it


def convert(case_dir, style, drift, dec, out, overrides):
    os.makedirs(out, exist_ok=True)
    case = stem(style, drift, dec)
    odom_t, odom, scans, truth = read_case(os.path.join(case_dir, case + ".mcap"))
    if not scans or not truth:
        sys.exit(f"{case}: no scans or no /ground_truth in the MCAP")
    with open(os.path.join(out, "run.log"), "w") as f:
        f.write(f"# {case}: one ROBOTLASER1 per scan, drift odometry from /odom (laser at base_link)\n")
        for m in scans:
            f.write(robotlaser_line(m, odom_at(odom_t, odom, m["stamp_ns"])))

    # The map: MRPT rounds the grid's corner to whole cells (COccupancyGridMap2D::setSize), so
    # the origin is rounded here and the difference (shift) added to poses into MRPT's frame.
    image, res, origin = read_yaml_map(os.path.join(case_dir, style, "map.yaml"))
    if abs(origin[2]) > 1e-9:
        sys.exit(f"{style}/map.yaml: origin yaw {origin[2]} (MRPT ignores it)")
    ox, oy = res * round(origin[0] / res), res * round(origin[1] / res)
    shift = (ox - origin[0], oy - origin[1])
    shutil.copyfile(os.path.join(case_dir, style, image), os.path.join(out, "map.pgm"))
    with open(os.path.join(out, "map.yaml"), "w") as f:
        # pgm: occupied 0, free 254, unknown 205 (1 - 205/255 = 0.196: ROS's default free_thresh
        # exactly, so a clear threshold here).
        f.write(f"image: map.pgm\nresolution: {res!r}\norigin: [{ox!r}, {oy!r}, 0.0]\n"
                "negate: false\noccupied_thresh: 0.65\nfree_thresh: 0.1\n")

    # The config: MRPT's shipped one for observation-only rawlogs (what carmen2rawlog writes),
    # only the files, the particle count, the start and the output volume changed.
    t0 = min(truth)
    x0, y0, w0 = truth[t0][0] + shift[0], truth[t0][1] + shift[1], math.degrees(truth[t0][2])
    # Uniform box with polyloc's sigmas (pf-localization has no Gaussian start): half-width sqrt(3) sigma.
    hx, hw = math.sqrt(3) * INIT_SIGMA_XY, math.sqrt(3) * INIT_SIGMA_YAW_DEG
    ini = open(SHIPPED_INI).read()
    L = "LocalizationExperiment"
    for k, v in [("map_file", os.path.abspath(os.path.join(out, "map.gridmap.gz"))),
                 ("rawlog_file", os.path.abspath(os.path.join(out, "run.rawlog"))),
                 ("logOutput_dir", os.path.abspath(os.path.join(out, "mrpt"))),
                 ("particles_count", PARTICLES),
                 ("init_PDF_mode", 1),  # uniform in the box (0: only on free cells)
                 ("init_PDF_min_x", x0 - hx), ("init_PDF_max_x", x0 + hx),
                 ("init_PDF_min_y", y0 - hx), ("init_PDF_max_y", y0 + hx),
                 ("init_PDF_min_yaw_deg", w0 - hw), ("init_PDF_max_yaw_deg", w0 + hw),
                 ("3DSceneFrequency", -1),  # no 3D scene / particle files per step (I/O only)
                 ("SHOW_PROGRESS_3D_REAL_TIME", "false"),
                 ("SAVE_STATS_ONLY", "false")]:  # false: the per-step "PDF estimation" lines we read
        ini = set_ini(ini, L, k, v)
    # A fixed 3,000 (the shipped config adapts the count by KLD, 150 .. 40,000).
    ini = set_ini(ini, "PF_options", "adaptiveSampleSize", 0)
    for o in overrides:  # SECTION.KEY=VALUE from the command line
        sk, v = o.split("=", 1)
        s, k = sk.split(".", 1)
        ini = set_ini(ini, s, k, v)
    open(os.path.join(out, "pf.ini"), "w").write(ini)
    json.dump({"case": case, "shift": shift, "scan_stamps": [m["stamp_ns"] for m in scans],
               "truth": {str(t): p for t, p in truth.items()}, "beams": len(scans[0]["ranges"]),
               "overrides": overrides}, open(os.path.join(out, "case.json"), "w"))
    print(f"{out}: {len(scans)} scans of {len(scans[0]['ranges'])} beams, map shift {shift[0]:+.4f} {shift[1]:+.4f} m",
          file=sys.stderr)


def errors(est, truth, frames):
    e = np.array([math.hypot(est[t][0] - truth[t][0], est[t][1] - truth[t][1]) for t in frames])
    yaw = np.array([abs(math.remainder(est[t][2] - truth[t][2], 2 * math.pi)) for t in frames])
    return {"ate_m": float(np.sqrt(np.mean(e ** 2))), "p95_m": float(np.percentile(e, 95)), "max_m": float(e.max()),
            "yaw_rmse_deg": float(np.degrees(np.sqrt(np.mean(yaw ** 2))))}


def score(case_dir, style, drift, dec, out, mrpt_stdout):
    case = stem(style, drift, dec)
    c = json.load(open(os.path.join(out, "case.json")))
    truth = {int(t): p for t, p in c["truth"].items()}
    sx, sy = c["shift"]
    # "PDF estimation: (x,y,phi_deg deg), ESS ..." (1 mm, 0.01 deg) once per laser observation, in
    # rawlog order: the rawlog's stamps cannot be used (carmen2rawlog turns CARMEN seconds into
    # 1e-6 x seconds microseconds after its own start time: every observation gets one stamp).
    num = r"(-?[\d.]+(?:e[-+]?\d+)?)"
    mrpt, ms = [], []
    for line in open(mrpt_stdout):
        if (m := re.search(rf"PDF estimation: \[?\(?{num}[ ,]+{num}[ ,]+{num}", line)):
            mrpt.append((float(m[1]) - sx, float(m[2]) - sy, math.radians(float(m[3]))))
        elif (m := re.search(r"Done in ([\d.]+)ms", line)):
            ms.append(float(m[1]))
    stamps = c["scan_stamps"]
    if len(mrpt) != len(stamps):
        sys.exit(f"MRPT gave {len(mrpt)} estimates for {len(stamps)} scans ({mrpt_stdout})")
    mrpt = dict(zip(stamps, mrpt))
    ours, ours_err = {}, {}
    with open(os.path.join(case_dir, case + ".csv")) as f:
        head = f.readline().strip().split(",")
        for row in f:
            r = dict(zip(head, row.strip().split(",")))
            t = int(r["stamp_ns"])
            ours[t] = (float(r["x"]), float(r["y"]), math.radians(float(r["yaw_deg"])))
            if "pos_err_m" in r:
                ours_err[t] = float(r["pos_err_m"])
    frames = sorted(t for t in truth if t in mrpt and t in ours)
    p, q = errors(ours, truth, frames), errors(mrpt, truth, frames)
    res = {"map": style, "drift": drift, "decimate": int(dec), "frames": len(frames),
           "scans": len(stamps), "polyloc_frames": len(ours),
           "polyloc_ate_m": p["ate_m"], "mrpt_ate_m": q["ate_m"],
           "ratio": p["ate_m"] / q["ate_m"] if q["ate_m"] > 0 else None,
           "polyloc_p95_m": p["p95_m"], "mrpt_p95_m": q["p95_m"], "polyloc_max_m": p["max_m"], "mrpt_max_m": q["max_m"],
           "polyloc_yaw_rmse_deg": p["yaw_rmse_deg"], "mrpt_yaw_rmse_deg": q["yaw_rmse_deg"],
           "mrpt_ms_per_step": float(np.mean(ms)) if ms else None, "mrpt_particles": PARTICLES,
           "mrpt_overrides": c["overrides"]}
    if style == "noisy":  # eval carmen warps the mesh, not the grid it saves
        res["note"] = "noisy: MRPT gets the unwarped grid, polyloc the warped mesh (not the same map)"
    if ours_err:  # polyloc's own per-frame error on these frames: a check that both are scored alike
        res["polyloc_ate_m_own_csv"] = float(np.sqrt(np.mean([ours_err[t] ** 2 for t in frames if t in ours_err])))
    return res


def main():
    if len(sys.argv) < 7 or sys.argv[1] not in ("convert", "score"):
        sys.exit(__doc__)
    if sys.argv[1] == "convert":
        convert(*sys.argv[2:7], sys.argv[7:])
    else:
        print(json.dumps(score(*sys.argv[2:8])))


if __name__ == "__main__":
    main()
