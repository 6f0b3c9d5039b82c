#!/usr/bin/env bash
# polyloc map fuse: 31 real Kinect frames of the shared 7-Scenes kitchen fused into a PLY that
# `polyloc map info` loads, with its PNG and JSON report; a folder with a broken pose file fuses
# the frames that have one; bad options and inputs give errors that name them.
set -Eeuo pipefail
trap 'rc=$?; echo "${0##*/}:$LINENO: exit $rc from: $BASH_COMMAND" >&2' ERR  # name the line a silent failure stops at
polyloc=$1
src=$2
kitchen="$src/../shared/data/rgbd/7scenes-redkitchen"
[ -d "$kitchen" ] || { echo "skipped: $kitchen is not here"; exit 0; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# Frames 0, 3, ..., 90 linked into a folder of their own (frame numbers, so stamps and poses, kept):
# the reader then decodes 31 images, not 1000.
mkdir "$tmp/k31"
cp "$kitchen/camera-intrinsics.txt" "$tmp/k31/"
for n in $(seq 0 3 90); do
  f=$(printf 'frame-%06d' "$n")
  ln -s "$kitchen/$f.depth.png" "$tmp/k31/$f.depth.png"
  ln -s "$kitchen/$f.pose.txt" "$tmp/k31/$f.pose.txt"
done
out=$("$polyloc" map fuse --input "$tmp/k31" --triangles 40000 --out "$tmp/k.ply" --plot "$tmp/k.png" --json)
python3 - "$out" <<'PY'
import json, sys
j = json.loads(sys.argv[1])
f, m = j["frames"], j["mesh"]
assert j["image_topic"] == "/depth/camera/image", j
assert f["images"] == 31 and f["selected"] == 31 and f["fused"] == 31 and f["without_pose"] == 0, f
assert j["camera"]["fx"] == 585 and j["camera"]["cx"] == 320, j["camera"]
# Decimated to the budget from marching cubes' mesh; a kitchen of a few metres, not a point.
assert 30000 < m["triangles"] <= 40000 < j["fusion"]["triangles_marched"], (m, j["fusion"])
size = [hi - lo for lo, hi in zip(m["bounds_min"], m["bounds_max"])]
assert all(1.0 < s < 6.0 for s in size), size
PY
[ -s "$tmp/k.png" ]
# The same map byte for byte on one thread (Open3D integrates with OpenMP).
OMP_NUM_THREADS=1 "$polyloc" map fuse --input "$tmp/k31" --triangles 40000 --out "$tmp/k1.ply" --json >/dev/null
cmp "$tmp/k.ply" "$tmp/k1.ply"
info=$("$polyloc" map info "$tmp/k.ply" --json)
grep -q '"triangles":[34][0-9]\{4\}' <<<"$info"

# Three frames, two pose files broken: one fused, two counted without a pose (the next pose
# is not within 50 ms to interpolate from).
mkdir "$tmp/three"
for n in 000000 000001 000002; do cp "$kitchen/frame-$n.depth.png" "$kitchen/frame-$n.pose.txt" "$tmp/three/"; done
echo "1 0 0" >"$tmp/three/frame-000001.pose.txt"
echo "1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 nan" >"$tmp/three/frame-000002.pose.txt"
out=$("$polyloc" map fuse --input "$tmp/three" --out "$tmp/three.ply" --json 2>"$tmp/err")
grep -q '"fused":1,' <<<"$out"
grep -q '"without_pose":2' <<<"$out"
grep -q 'frame-000002.pose.txt.*not a finite number' "$tmp/err"
# A map left in the data set's folder by an earlier run may be written again; its images may not.
"$polyloc" map fuse --input "$tmp/three" --out "$tmp/three/map.ply" --json >/dev/null 2>&1
"$polyloc" map fuse --input "$tmp/three" --out "$tmp/three/map.ply" --json >/dev/null 2>&1

# Errors name what is wrong.
if err=$("$polyloc" map fuse --input "$kitchen" --frames 5:2 --out "$tmp/x.ply" 2>&1); then exit 1; fi
grep -q "frames '5:2'" <<<"$err"
if err=$("$polyloc" map fuse --input "$tmp/three" --out "$tmp/three/frame-000000.depth.png" 2>&1); then exit 1; fi
grep -qi 'input' <<<"$err"
mkdir "$tmp/empty"
if err=$("$polyloc" map fuse --input "$tmp/empty" --out "$tmp/x.ply" 2>&1); then exit 1; fi
grep -q 'not a recording' <<<"$err"
rm "$tmp/three/"*.pose.txt
if err=$("$polyloc" map fuse --input "$tmp/three" --out "$tmp/x.ply" 2>&1); then exit 1; fi
grep -q 'nothing fused' <<<"$err"
if err=$("$polyloc" map fuse --input "$kitchen" --voxel 1e19 --out "$tmp/x.ply" 2>&1); then exit 1; fi
grep -q 'voxel' <<<"$err"
echo "map fuse: ok"
