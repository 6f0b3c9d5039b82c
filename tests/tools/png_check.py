#!/usr/bin/env python3
"""Check what a PNG written by polyloc shows, not only that it exists (stdlib only: zlib, struct).

    python3 tests/tools/png_check.py FILE [checks...]

Decodes 8-bit grey, grey+alpha, RGB and RGBA PNGs without interlacing (what OpenCV's imwrite
writes); anything else fails with a message saying what the file is. Checks (all optional, any
number of --colour):

  --size WxH              the picture is exactly W x H pixels
  --min-size WxH          at least W wide and H high
  --min-colours N         at least N distinct colours (a blank picture has 1)
  --ink A,B               the share of pixels that differ from the background (--background,
                          default: the most common colour) is within [A, B]
  --background RRGGBB     the background colour for --ink (hex)
  --colour NAME=RRGGBB:TOL:K
                          at least K pixels within TOL (per channel, 0-255) of the colour:
                          e.g. truth=285ADC:40:500 for polyloc's ground-truth blue; several
                          colours joined by + count the pixels near any of them
                          (path=285ADC+F08C14:40:500)
  --no-colour NAME=RRGGBB:TOL:K
                          fewer than K such pixels (a colour that must not be drawn)

Prints one line of figures (size, colours, ink, each colour's count) and exits 0 when every
check holds; 1 with a line per failed check; 2 when the file is no PNG it can read.
Alpha is ignored (polyloc writes opaque pictures). As a module: decode(path) -> (w, h, rows)
with rows a list of bytes objects of 3 * w (RGB) each.
"""
import argparse
import collections
import itertools
import struct
import sys
import zlib

SIGNATURE = b"\x89PNG\r\n\x1a\n"
CHANNELS = {0: 1, 2: 3, 4: 2, 6: 4}  # colour type -> samples per pixel
TYPE_NAMES = {0: "grey", 2: "RGB", 3: "palette", 4: "grey+alpha", 6: "RGBA"}


class PngError(Exception):
    pass


def _chunks(data, path):
    if data[:8] != SIGNATURE:
        raise PngError(f"{path}: not a PNG (first bytes {data[:8]!r})")
    pos = 8
    while pos < len(data):
        if pos + 8 > len(data):
            raise PngError(f"{path}: truncated chunk header at byte {pos}")
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        if len(body) != length or pos + 12 + length > len(data):
            raise PngError(f"{path}: chunk {kind!r} at byte {pos} is truncated")
        (crc,) = struct.unpack(">I", data[pos + 8 + length:pos + 12 + length])
        if zlib.crc32(kind + body) & 0xFFFFFFFF != crc:
            raise PngError(f"{path}: chunk {kind!r} at byte {pos} has a bad CRC")
        yield kind, body
        pos += 12 + length
        if kind == b"IEND":
            return
    raise PngError(f"{path}: no IEND chunk (truncated file)")


def _unfilter_row(ftype, line, prev, bpp):
    """Undo one scanline's filter (PNG spec 9.2); line and prev are bytearrays of equal length."""
    n = len(line)
    if ftype == 0:
        return line
    if ftype == 1:  # Sub: a running sum per channel, mod 256 (itertools and map keep it in C)
        for c in range(bpp):
            line[c::bpp] = bytearray(map((0xFF).__and__, itertools.accumulate(line[c::bpp])))
        return line
    if ftype == 2:  # Up
        return bytearray(map((0xFF).__and__, map(int.__add__, line, prev)))
    if ftype == 3:  # Average
        for i in range(n):
            left = line[i - bpp] if i >= bpp else 0
            line[i] = (line[i] + ((left + prev[i]) >> 1)) & 0xFF
        return line
    if ftype == 4:  # Paeth
        for i in range(n):
            b = prev[i]
            if i >= bpp:
                a, c = line[i - bpp], prev[i - bpp]
            else:
                a = c = 0
            p = a + b - c
            pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
            if pa <= pb and pa <= pc:
                pred = a
            elif pb <= pc:
                pred = b
            else:
                pred = c
            line[i] = (line[i] + pred) & 0xFF
        return line
    raise PngError(f"unknown filter type {ftype}")


def decode(path):
    """(width, height, rows): rows[y] is bytes of 3 * width, RGB (grey expanded, alpha dropped)."""
    with open(path, "rb") as f:
        data = f.read()
    header, idat = None, []
    for kind, body in _chunks(data, path):
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat.append(body)
    if header is None:
        raise PngError(f"{path}: no IHDR chunk")
    width, height, depth, ctype, comp, filt, interlace = header
    if ctype not in CHANNELS or depth != 8:
        raise PngError(f"{path}: {TYPE_NAMES.get(ctype, f'colour type {ctype}')} at {depth} bits per sample; "
                       "png_check reads 8-bit grey, grey+alpha, RGB and RGBA only")
    if interlace != 0:
        raise PngError(f"{path}: interlaced (Adam7); png_check reads non-interlaced PNGs only")
    if comp != 0 or filt != 0:
        raise PngError(f"{path}: compression method {comp} / filter method {filt} (the standard has only 0)")
    if width == 0 or height == 0:
        raise PngError(f"{path}: empty picture {width}x{height}")
    if not idat:
        raise PngError(f"{path}: no IDAT chunk")
    try:
        raw = zlib.decompress(b"".join(idat))
    except zlib.error as e:
        raise PngError(f"{path}: image data does not inflate ({e})")
    bpp = CHANNELS[ctype]
    stride = width * bpp
    if len(raw) != height * (stride + 1):
        raise PngError(f"{path}: {len(raw)} bytes of image data, expected {height * (stride + 1)} for "
                       f"{width}x{height} {TYPE_NAMES[ctype]}")
    rows = []
    prev = bytearray(stride)
    for y in range(height):
        start = y * (stride + 1)
        ftype = raw[start]
        line = bytearray(raw[start + 1:start + 1 + stride])
        if ftype > 4:
            raise PngError(f"{path}: row {y} has filter type {ftype} (0-4 exist)")
        line = _unfilter_row(ftype, line, prev, bpp)
        prev = line
        if ctype == 2:
            rows.append(bytes(line))
        elif ctype == 6:
            rgb = bytearray(3 * width)
            rgb[0::3], rgb[1::3], rgb[2::3] = line[0::4], line[1::4], line[2::4]
            rows.append(bytes(rgb))
        else:  # grey, grey+alpha
            g = line[0::bpp]
            rgb = bytearray(3 * width)
            rgb[0::3], rgb[1::3], rgb[2::3] = g, g, g
            rows.append(bytes(rgb))
    return width, height, rows


def histogram(width, rows):
    """Counter of (r, g, b) -> pixels."""
    counts = collections.Counter()
    for row in rows:
        # Rows of one colour (most of a plot's margin) are counted at once.
        if row == row[:3] * width:
            counts[tuple(row[:3])] += width
            continue
        counts.update(zip(row[0::3], row[1::3], row[2::3]))
    return counts


def near(counts, colours, tol):
    """Pixels within tol (per channel) of any of the colours ((r, g, b) tuples)."""
    total = 0
    for (r, g, b), n in counts.items():
        if any(abs(r - r0) <= tol and abs(g - g0) <= tol and abs(b - b0) <= tol for r0, g0, b0 in colours):
            total += n
    return total


def _hex(s):
    s = s.lstrip("#")
    if len(s) != 6:
        raise argparse.ArgumentTypeError(f"colour {s!r}: expected RRGGBB (hex)")
    return tuple(int(s[i:i + 2], 16) for i in (0, 2, 4))


def _colour_spec(s):
    try:
        name, rest = s.split("=", 1)
        rgb, tol, k = rest.split(":")
        return name, tuple(_hex(c) for c in rgb.split("+")), int(tol), int(k)
    except (ValueError, argparse.ArgumentTypeError):
        raise argparse.ArgumentTypeError(f"{s!r}: expected NAME=RRGGBB[+RRGGBB...]:TOL:K, e.g. truth=285ADC:40:500")


def _names(colours):
    return " or ".join("#" + bytes(c).hex().upper() for c in colours)


def _wxh(s):
    try:
        w, h = s.lower().split("x")
        return int(w), int(h)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{s!r}: expected WxH, e.g. 640x480")


def _range(s):
    try:
        a, b = (float(v) for v in s.split(","))
        return a, b
    except ValueError:
        raise argparse.ArgumentTypeError(f"{s!r}: expected A,B (shares in 0..1), e.g. 0.01,0.5")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("png")
    ap.add_argument("--size", type=_wxh)
    ap.add_argument("--min-size", type=_wxh)
    ap.add_argument("--min-colours", type=int)
    ap.add_argument("--ink", type=_range)
    ap.add_argument("--background", type=_hex)
    ap.add_argument("--colour", type=_colour_spec, action="append", default=[])
    ap.add_argument("--no-colour", type=_colour_spec, action="append", default=[])
    args = ap.parse_args(argv)

    try:
        width, height, rows = decode(args.png)
    except (PngError, OSError) as e:
        print(f"png_check: {e}", file=sys.stderr)
        return 2
    counts = histogram(width, rows)
    total = width * height
    background = args.background
    bg_key = tuple(background) if background else counts.most_common(1)[0][0]
    ink = 1.0 - counts.get(bg_key, 0) / total
    bg_hex = bytes(bg_key).hex().upper()
    found = {name: near(counts, rgb, tol) for name, rgb, tol, _ in args.colour + args.no_colour}
    print(f"png_check {args.png}: {width}x{height}, {len(counts)} colours, ink {ink:.4f} "
          f"(background #{bg_hex})" + "".join(f", {n} {v} px" for n, v in found.items()))

    failures = []
    if args.size and (width, height) != args.size:
        failures.append(f"size {width}x{height}, expected {args.size[0]}x{args.size[1]}")
    if args.min_size and (width < args.min_size[0] or height < args.min_size[1]):
        failures.append(f"size {width}x{height}, expected at least {args.min_size[0]}x{args.min_size[1]}")
    if args.min_colours is not None and len(counts) < args.min_colours:
        failures.append(f"{len(counts)} distinct colours, expected at least {args.min_colours} (a blank picture?)")
    if args.ink and not args.ink[0] <= ink <= args.ink[1]:
        failures.append(f"{ink:.4f} of the pixels differ from the background #{bg_hex}, "
                        f"expected {args.ink[0]} to {args.ink[1]}")
    for name, rgb, tol, k in args.colour:
        if found[name] < k:
            failures.append(f"{name}: {found[name]} pixels within {tol} of {_names(rgb)}, "
                            f"expected at least {k} (not drawn?)")
    for name, rgb, tol, k in args.no_colour:
        if found[name] >= k:
            failures.append(f"{name}: {found[name]} pixels within {tol} of {_names(rgb)}, "
                            f"expected fewer than {k}")
    for f in failures:
        print(f"png_check {args.png}: FAIL {f}", file=sys.stderr)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
