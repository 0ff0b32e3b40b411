"""The vocabulary the app builds on: ARKit's names and keys, the methods,
the version."""

import re


def test_arkit_names_and_keys_name_the_same_52_shapes_in_order(ffi):
    names, keys = ffi.arkit_names(), ffi.arkit_keys()
    assert len(names) == len(set(names)) == 52
    assert len(keys) == len(set(keys)) == 52
    assert (names[0], keys[0]) == ("eyeBlinkLeft", "eyeBlink_L")
    assert names[-1] == keys[-1] == "tongueOut"
    for name, key in zip(names, keys):
        # Apple abbreviates the side, except where it is the direction of
        # motion (jawLeft, mouthRight, ...).
        expected = re.sub(r"Left$", "_L", re.sub(r"Right$", "_R", name))
        if name in ("jawLeft", "jawRight", "mouthLeft", "mouthRight"):
            expected = name
        assert key == expected


def test_methods_and_the_default(ffi):
    methods = ffi.methods()
    assert [m.name for m in methods] == ["dt", "ebfr", "paper", "paper-cv", "multi"]
    assert all(len(m.description) > 20 for m in methods)
    assert ffi.default_method() == "multi"
    assert "(the default)" in methods[-1].description


def test_the_core_version_is_the_workspace_version(ffi):
    from conftest import REPO

    manifest = (REPO / "Cargo.toml").read_text()
    version = re.search(r'\[workspace\.package\][^\[]*?version = "([^"]+)"', manifest).group(1)
    assert ffi.core_version() == version
