#!/usr/bin/env python3
"""Writes a synthetic lat-long sky as a Radiance HDR (flat RGBE, no dependencies): a blue
gradient sky, a dim ground and a small sun disc, in the EnvironmentLight convention
(docs/lights.md: row 0 at the top, u = atan2(x, -z) / (2 pi), Mitsuba's). For measuring environment
lighting on scenes that ship without a sky.

    python3 tools/make_sky_hdr.py OUT.hdr [--width 512] [--sun-elevation 35] [--sun-azimuth 60]
"""
import argparse
import math
import struct


def rgbe(r, g, b):
    m = max(r, g, b)
    if m < 1e-32:
        return bytes((0, 0, 0, 0))
    mant, exp = math.frexp(m)
    scale = mant * 256.0 / m
    return bytes((int(r * scale), int(g * scale), int(b * scale), exp + 128))


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("out")
    p.add_argument("--width", type=int, default=512)
    p.add_argument("--sun-elevation", type=float, default=35.0, help="degrees above the horizon")
    p.add_argument("--sun-azimuth", type=float, default=60.0, help="degrees, 0 = -Z, 90 = +X")
    p.add_argument("--sun-radius", type=float, default=1.5, help="angular radius, degrees")
    p.add_argument("--sun-radiance", type=float, default=2000.0)
    a = p.parse_args()
    w, h = a.width, a.width // 2
    el, az = math.radians(a.sun_elevation), math.radians(a.sun_azimuth)
    sun = (math.cos(el) * math.sin(az), math.sin(el), -math.cos(el) * math.cos(az))
    cos_sun = math.cos(math.radians(a.sun_radius))
    rows = []
    for y in range(h):
        theta = (y + 0.5) / h * math.pi
        row = bytearray()
        for x in range(w):
            phi = (x + 0.5) / w * 2 * math.pi
            d = (math.sin(theta) * math.sin(phi), math.cos(theta), -math.sin(theta) * math.cos(phi))
            if d[0] * sun[0] + d[1] * sun[1] + d[2] * sun[2] >= cos_sun:
                c = (a.sun_radiance, 0.9 * a.sun_radiance, 0.75 * a.sun_radiance)
            elif d[1] >= 0:
                t = d[1]
                c = (0.35 + 0.25 * (1 - t), 0.55 + 0.2 * (1 - t), 1.0)
            else:
                c = (0.12, 0.1, 0.08)
            row += rgbe(*c)
        rows.append(bytes(row))
    with open(a.out, "wb") as f:
        f.write(b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n")
        f.write(f"-Y {h} +X {w}\n".encode())
        for r in rows:
            f.write(r)


if __name__ == "__main__":
    main()
