"""The app icon (pytest): ios-app/tools/make_app_icon.py draws exactly the
committed icon, and the icon is what the App Store takes (1024 x 1024, RGB,
no alpha). Pixels are compared, not file bytes: PNG compression may differ
between zlib builds while the picture does not."""
from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

from PIL import Image

REPO = Path(__file__).resolve().parents[2]
SCRIPT = REPO / "ios-app" / "tools" / "make_app_icon.py"
ASSETS = REPO / "ios-app" / "Likeness" / "Assets.xcassets"
ICON = ASSETS / "AppIcon.appiconset" / "AppIcon-1024.png"


def test_the_script_draws_the_committed_icon(tmp_path):
    subprocess.run([sys.executable, str(SCRIPT), "--assets", str(tmp_path)], check=True, capture_output=True)
    drawn = tmp_path / "AppIcon.appiconset" / "AppIcon-1024.png"
    with Image.open(drawn) as new, Image.open(ICON) as committed:
        assert new.mode == committed.mode
        assert new.size == committed.size
        assert new.tobytes() == committed.tobytes(), "the committed icon is not what make_app_icon.py draws: rerun it"
    for contents in ("Contents.json", "AppIcon.appiconset/Contents.json"):
        assert json.loads((tmp_path / contents).read_text()) == json.loads((ASSETS / contents).read_text())


def test_the_icon_is_1024_square_rgb_without_alpha():
    with Image.open(ICON) as icon:
        assert icon.format == "PNG"
        assert icon.size == (1024, 1024)
        assert icon.mode == "RGB"
        assert "transparency" not in icon.info


def test_the_catalog_names_the_icon_for_every_ios_size():
    contents = json.loads((ASSETS / "AppIcon.appiconset" / "Contents.json").read_text())
    assert contents["images"] == [
        {"filename": "AppIcon-1024.png", "idiom": "universal", "platform": "ios", "size": "1024x1024"}
    ]
