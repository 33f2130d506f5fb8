#!/usr/bin/env python3
"""Makes incise's procedural tissue textures: scenarios/textures/skin.png and flesh.png, 256 x 256 RGB,
tileable (every noise is periodic over the image), from nothing but this script (no image from elsewhere).

  skin   pale pink-beige, mottled, with fine pores and faint creases
  flesh  the wound's walls: deep red muscle with fibres along u (the walls' u runs along the stroke, so the
         fibres follow the wound) and pale fascia streaks

Usage: make_textures.py [OUT_DIR]   (default: scenarios/textures beside this script's folder)
       make_textures.py --check DIR (exit 1 unless DIR's images hold exactly the pixels this script makes)

Pure Python (zlib, struct): the pixels are the same on every machine; the PNG bytes depend on zlib's
compressor, so --check compares the decoded pixels. Takes about two seconds.
"""
import math
import pathlib
import struct
import sys
import zlib

SIZE = 256


def lattice(ix, iy, seed):
    """A pseudo-random value in [0, 1) per integer lattice point (an integer hash: the same everywhere)."""
    h = (ix * 374761393 + iy * 668265263 + seed * 2147483647) & 0xFFFFFFFF
    h = ((h ^ (h >> 13)) * 1274126177) & 0xFFFFFFFF
    return ((h ^ (h >> 16)) & 0xFFFFFF) / float(1 << 24)


def value_noise(x, y, period_x, period_y, seed):
    """Smooth value noise at (x, y) in lattice units, periodic over period_x by period_y cells."""
    x0, y0 = math.floor(x), math.floor(y)
    fx, fy = x - x0, y - y0
    sx, sy = fx * fx * (3 - 2 * fx), fy * fy * (3 - 2 * fy)
    a = lattice(x0 % period_x, y0 % period_y, seed)
    b = lattice((x0 + 1) % period_x, y0 % period_y, seed)
    c = lattice(x0 % period_x, (y0 + 1) % period_y, seed)
    d = lattice((x0 + 1) % period_x, (y0 + 1) % period_y, seed)
    top, bottom = a + (b - a) * sx, c + (d - c) * sx
    return top + (bottom - top) * sy


def fractal(u, v, cells_u, cells_v, octaves, seed):
    """Octaves of value noise over the unit square [0, 1)^2, tileable, in [0, 1]."""
    total, weight, amplitude = 0.0, 0.0, 1.0
    for octave in range(octaves):
        scale = 1 << octave
        total += amplitude * value_noise(u * cells_u * scale, v * cells_v * scale, cells_u * scale,
                                         cells_v * scale, seed + octave)
        weight += amplitude
        amplitude *= 0.5
    return total / weight


def mix(a, b, t):
    return tuple(x + (y - x) * t for x, y in zip(a, b))


def skin(u, v):
    mottle = fractal(u, v, 4, 4, 4, 11)
    pores = fractal(u, v, 32, 32, 2, 23)
    crease = abs(fractal(u, v, 3, 5, 2, 37) - 0.5)
    base = mix((0.80, 0.60, 0.52), (0.92, 0.74, 0.66), mottle)
    shade = 1.0 - 0.06 * max(0.0, pores - 0.6) / 0.4 - 0.05 * max(0.0, 0.04 - crease) / 0.04
    return tuple(c * shade for c in base)


def flesh(u, v):
    fibres = fractal(u, v, 2, 32, 2, 5)  # long along u, fine across v
    blotch = fractal(u, v, 4, 4, 3, 17)
    fascia = max(0.0, fractal(u, v, 1, 12, 2, 29) - 0.68) / 0.32
    base = mix((0.42, 0.06, 0.07), (0.72, 0.18, 0.16), 0.55 * fibres + 0.45 * blotch)
    return mix(base, (0.86, 0.72, 0.68), 0.7 * fascia)


def pixels(shade):
    rows = []
    for y in range(SIZE):
        row = bytearray()
        for x in range(SIZE):
            rgb = shade(x / SIZE, y / SIZE)
            row += bytes(max(0, min(255, int(round(255 * c)))) for c in rgb)
        rows.append(bytes(row))
    return rows


def png(rows):
    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    header = struct.pack(">IIBBBBB", SIZE, SIZE, 8, 2, 0, 0, 0)  # 8-bit RGB
    raw = b"".join(b"\x00" + row for row in rows)  # filter 0 on every row
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b"")


def decoded_rows(data):
    """The rows of an 8-bit RGB PNG with filter 0 on every row (as png() writes), else None."""
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        return None
    at, idat, header = 8, b"", None
    while at < len(data):
        (length,) = struct.unpack(">I", data[at:at + 4])
        kind, body = data[at + 4:at + 8], data[at + 8:at + 8 + length]
        if kind == b"IHDR":
            header = body
        elif kind == b"IDAT":
            idat += body
        at += 12 + length
    if header != struct.pack(">IIBBBBB", SIZE, SIZE, 8, 2, 0, 0, 0):
        return None
    raw = zlib.decompress(idat)
    stride = 1 + 3 * SIZE
    if len(raw) != stride * SIZE or any(raw[r * stride] != 0 for r in range(SIZE)):
        return None
    return [raw[r * stride + 1:(r + 1) * stride] for r in range(SIZE)]


TEXTURES = {"skin.png": skin, "flesh.png": flesh}


def main(argv):
    here = pathlib.Path(__file__).resolve().parent.parent / "scenarios" / "textures"
    if len(argv) >= 2 and argv[0] == "--check":
        folder = pathlib.Path(argv[1])
        bad = [name for name, shade in TEXTURES.items()
               if not (folder / name).is_file() or decoded_rows((folder / name).read_bytes()) != pixels(shade)]
        for name in bad:
            print(f"{folder / name}: not the pixels scripts/make_textures.py makes (run it to remake them)")
        return 1 if bad else 0
    folder = pathlib.Path(argv[0]) if argv else here
    folder.mkdir(parents=True, exist_ok=True)
    for name, shade in TEXTURES.items():
        path = folder / name
        tmp = path.with_suffix(".png.tmp")
        tmp.write_bytes(png(pixels(shade)))
        tmp.replace(path)
        print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
