#!/usr/bin/env python3
"""Writes bumps_normal_256.png: the tangent-space normal map of 32 x 32 smooth round bumps
(h = cos^2 of the distance to each bump's centre, 8 texels per bump, slopes up to ~0.6), the
normal-mapped floor of the specular anti-aliasing study
(scenes/studies/scenes/specular-bumps.toml). Encoding: c = (n + 1) / 2 in 8-bit RGB, linear
(no sRGB curve), +x along u and +y along v. Standard library and Pillow (the project's venv):

    .venv/bin/python scenes/assets/make_bumps_normal.py
"""

import math
import os

from PIL import Image

SIZE, PERIOD, HEIGHT = 256, 8, 0.9  # texels, texels per bump, bump height in texels
image = Image.new("RGB", (SIZE, SIZE))
pixels = []
for y in range(SIZE):
    for x in range(SIZE):
        # Position within the bump cell, centre at 0, in [-0.5, 0.5); texel centres.
        u = ((x + 0.5) % PERIOD) / PERIOD - 0.5
        v = ((y + 0.5) % PERIOD) / PERIOD - 0.5
        r = math.hypot(u, v)
        # h(r) = HEIGHT * cos^2(pi r) inside r < 0.5; dh/dr = -HEIGHT * pi * sin(2 pi r).
        if r < 0.5 and r > 0.0:
            dhdr = -HEIGHT * math.pi * math.sin(2.0 * math.pi * r) / PERIOD
            gx, gy = dhdr * u / r, dhdr * v / r
        else:
            gx = gy = 0.0
        n = (-gx, -gy, 1.0)
        length = math.sqrt(sum(c * c for c in n))
        pixels.append(tuple(round(255 * (c / length + 1.0) / 2.0) for c in n))
image.putdata(pixels)
out = os.path.join(os.path.dirname(os.path.abspath(__file__)), "bumps_normal_256.png")
image.save(out, optimize=True)
print(out)
