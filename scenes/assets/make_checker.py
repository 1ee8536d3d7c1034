"""Writes checker_512.png: a 512 x 512 black-and-white checkerboard of 8-texel squares (64 x 64
squares), 8-bit grey, the texture of the texture-filtering studies
(scenes/studies/scenes/texture-plane.toml). Black and white are exact in sRGB and linear, so
its mean is 0.5 in linear radiance and the sRGB-space MIP mistake shows as 0.214.

    python3 scenes/assets/make_checker.py   (needs Pillow; the project's venv has it)
"""

import os

from PIL import Image

SIZE, SQUARE = 512, 8
image = Image.new("L", (SIZE, SIZE))
image.putdata([255 if (x // SQUARE + y // SQUARE) % 2 == 0 else 0
               for y in range(SIZE) for x in range(SIZE)])
out = os.path.join(os.path.dirname(os.path.abspath(__file__)), "checker_512.png")
image.save(out, optimize=True)
print(out)
