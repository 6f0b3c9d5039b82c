#!/usr/bin/env python3
"""Writes the seed inputs of fuzz_shm_validate (fuzz/fuzz_shm_validate.cpp explains the modes)
into fuzz/corpus/fuzz_shm_validate. Run it again after changing the input format."""
import os
import struct

HERE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "fuzz_shm_validate")
NOW = 1_700_000_000_000_000_000
INT64_MIN = -(1 << 63)


def rules(last=INT64_MIN):
    return struct.pack("<qB", last, 0)


def scan(count, stamp, value=2.0):
    return struct.pack("<qII", stamp, count, 0) + struct.pack("<%df" % count, *([value] * count))


def odom(stamp, qw=1.0):
    return struct.pack("<q10d", stamp, 1, 2, 0, qw, 0, 0, 0, 0.1, 0, 0)


def depth(w, h, amp, stamp):
    n = w * h * (2 if amp else 1)
    return struct.pack("<qIIII", stamp, w, h, amp, 0) + struct.pack("<%df" % n, *([1.5] * n))


def validate(channel, payload, claimed=None, frame=1, last=INT64_MIN):
    size = 0x80000000 if claimed is None else claimed
    return bytes([0, channel]) + struct.pack("<IH", size, frame) + rules(last) + payload


def ring(channel, frames, slot_size, slots, payload_of):
    """Ring control + slots with frames 0..frames-1 complete, the newest `slots` in place."""
    control = struct.pack("<QIiQ", frames, frames, 0, 1) + bytes(40)
    body = bytearray(slot_size * slots)
    for n in range(max(0, frames - slots), frames):
        p = payload_of(n)
        hdr = struct.pack("<QIIqq", 2 * n + 2, len(p), 1, NOW, 1) + bytes(32)
        k = (n % slots) * slot_size
        body[k:k + len(hdr) + len(p)] = hdr + p
    return bytes([1, channel]) + control + bytes(body) + bytes([2]) + rules()


seeds = {
    "scan_ok": validate(0, scan(5, NOW)),
    "scan_short": validate(0, scan(5, NOW)[:20]),
    "scan_nan": validate(0, scan(5, NOW, float("nan"))),
    "scan_any_count": validate(1, scan(3, NOW)),
    "scan_huge_size": validate(0, scan(5, NOW), claimed=0xFFFFFFF0),
    "scan_stale": validate(0, scan(5, NOW - 10**9)),
    "depth_amp": validate(2, depth(3, 2, 1, NOW)),
    "depth_plain": validate(2, depth(3, 2, 0, NOW)),
    "odom_ok": validate(3, odom(NOW)),
    "odom_bad_quat": validate(3, odom(NOW, 0.5)),
    "pose_not_input": validate(4, bytes(440)),
    "ring_scan": ring(0, 6, 128, 4, lambda n: scan(5, NOW + n)),
    "ring_odom_torn": ring(3, 3, 192, 2, lambda n: odom(NOW + n))[:-40] + bytes(40),
    "attach_plain": bytes([2]),
    "attach_abi2": bytes([2]) + struct.pack("<HB", 8, 4) + struct.pack("<I", 2),
    "attach_count": bytes([2]) + struct.pack("<HB", 36, 4) + struct.pack("<I", 40),
    "attach_write_count": bytes([2]) + struct.pack("<HB", 3200, 8) + struct.pack("<Q", 5),
}
os.makedirs(HERE, exist_ok=True)
for name, data in seeds.items():
    with open(os.path.join(HERE, name), "wb") as f:
        f.write(data)
print(len(seeds), "seeds in", HERE)
