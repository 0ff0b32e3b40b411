#!/usr/bin/env python3
"""Draws the Likeness app icon and writes it into the app's asset catalog.

Usage::

    python3 ios-app/tools/make_app_icon.py [--assets PATH/Assets.xcassets]

Writes ``Assets.xcassets/Contents.json``,
``Assets.xcassets/AppIcon.appiconset/Contents.json`` and
``Assets.xcassets/AppIcon.appiconset/AppIcon-1024.png`` (default: the app's
catalog, ``ios-app/Likeness/Assets.xcassets``). The icon is one 1024 x 1024
image for every iOS size (Xcode 14 and later scale it), RGB without alpha as
the App Store requires.

The drawing is shapes only (no fonts, no randomness): a face mask on a
gradient, its right half drawn as the tracked mesh. It is drawn at four times
the size and averaged down four by four (Pillow's BOX filter), which gives
smooth edges and the same pixels on every run with the Pillow version pinned
in ``tests/python/requirements-swift.txt``; ``tests/python/test_app_icon.py``
checks that the committed PNG is what this script draws.
"""
from __future__ import annotations

import argparse
import json
from pathlib import Path

from PIL import Image, ImageChops, ImageDraw

SIZE = 1024
SCALE = 4  # drawn at SIZE * SCALE, averaged down

DEFAULT_ASSETS = Path(__file__).resolve().parents[1] / "Likeness" / "Assets.xcassets"
ICON_SET = "AppIcon.appiconset"
ICON_FILE = "AppIcon-1024.png"

TOP = (30, 27, 75)  # indigo
BOTTOM = (13, 110, 103)  # teal
SKIN = (246, 236, 222)
MESH = (20, 184, 166)
INK = (30, 27, 75)

# The face: an ellipse, in icon coordinates.
FACE_CENTRE = (512, 540)
FACE_RADII = (292, 362)

CATALOG_CONTENTS = {"info": {"author": "xcode", "version": 1}}
ICON_CONTENTS = {
    "images": [
        {"filename": ICON_FILE, "idiom": "universal", "platform": "ios", "size": "1024x1024"},
    ],
    "info": {"author": "xcode", "version": 1},
}


def s(value: float) -> int:
    """An icon coordinate on the large canvas."""
    return round(value * SCALE)


def box(cx: float, cy: float, rx: float, ry: float) -> tuple[int, int, int, int]:
    return (s(cx - rx), s(cy - ry), s(cx + rx), s(cy + ry))


def gradient(size: int) -> Image.Image:
    """Top to bottom, from TOP to BOTTOM."""
    image = Image.new("RGB", (size, size))
    draw = ImageDraw.Draw(image)
    for y in range(size):
        t = y / (size - 1)
        colour = tuple(round(a + (b - a) * t) for a, b in zip(TOP, BOTTOM))
        draw.line([(0, y), (size - 1, y)], fill=colour)
    return image


def face_mask(size: int) -> Image.Image:
    mask = Image.new("L", (size, size), 0)
    ImageDraw.Draw(mask).ellipse(box(*FACE_CENTRE, *FACE_RADII), fill=255)
    return mask


def mesh_layer(size: int) -> Image.Image:
    """The tracked mesh's lines: rows following the face's curve, columns
    bending towards its edge."""
    layer = Image.new("L", (size, size), 0)
    draw = ImageDraw.Draw(layer)
    cx, cy = FACE_CENTRE
    rx, ry = FACE_RADII
    width = s(7)
    for row in range(-5, 6):
        y = cy + row * ry / 6
        # A gentle arc across the face, like a mesh row over a cheek.
        draw.arc(box(cx, y - 140, rx * 1.2, 170), start=45, end=135, fill=255, width=width)
    for column in range(1, 6):
        x = column * rx / 6
        draw.arc(box(cx, cy, x, ry), start=-90, end=90, fill=255, width=width)
    return layer


def draw_icon() -> Image.Image:
    size = SIZE * SCALE
    image = gradient(size)
    face = face_mask(size)
    image.paste(Image.new("RGB", (size, size), SKIN), mask=face)

    # The mesh on the right half of the face only.
    right = Image.new("L", (size, size), 0)
    ImageDraw.Draw(right).rectangle((s(FACE_CENTRE[0]), 0, size, size), fill=255)
    lines = ImageChops.multiply(mesh_layer(size), ImageChops.multiply(face, right))
    image.paste(Image.new("RGB", (size, size), MESH), mask=lines)

    draw = ImageDraw.Draw(image)
    cx, cy = FACE_CENTRE
    # Brows, eyes, mouth.
    for side in (-1, 1):
        ex = cx + side * 112
        draw.arc(box(ex, cy - 95, 78, 40), start=200, end=340, fill=INK, width=s(16))
        draw.ellipse(box(ex, cy - 60, 58, 32), fill=INK)
    draw.arc(box(cx, cy + 70, 132, 110), start=25, end=155, fill=INK, width=s(26))
    return image.resize((SIZE, SIZE), Image.Resampling.BOX)


def write_catalog(assets: Path) -> Path:
    """Writes the catalog; returns the PNG's path."""
    icon_set = assets / ICON_SET
    icon_set.mkdir(parents=True, exist_ok=True)
    (assets / "Contents.json").write_text(json.dumps(CATALOG_CONTENTS, indent=2) + "\n", encoding="utf-8")
    (icon_set / "Contents.json").write_text(json.dumps(ICON_CONTENTS, indent=2) + "\n", encoding="utf-8")
    png = icon_set / ICON_FILE
    draw_icon().save(png, format="PNG", optimize=False)
    return png


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--assets", type=Path, default=DEFAULT_ASSETS,
                        help="the asset catalog folder (default: ios-app/Likeness/Assets.xcassets)")
    args = parser.parse_args(argv)
    png = write_catalog(args.assets)
    print(f"make_app_icon.py: wrote {png}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
