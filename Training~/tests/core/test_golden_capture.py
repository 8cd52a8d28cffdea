"""Tests/Data/capture_golden.lpnncap + .json (written by the C# GoldenWriter): same reader, same bytes."""

from __future__ import annotations

import numpy as np

from lpnn.core.capture_encoder import encode_capture
from lpnn.core.capture_file import read_capture, validate_capture
from lpnn.core.capture_format import KNOWN_HEADER_KEYS


def expected_header(listing: dict) -> dict:
    """Header fields of the listing: under "header" if present, else at its top level."""
    source = listing.get("header", listing)
    return {key: source[key] for key in KNOWN_HEADER_KEYS if key in source and key != "sections"}


def test_reader_finds_what_the_listing_says(golden_path, golden):
    path = golden_path("capture_golden.lpnncap")
    listing = golden("capture_golden.json")
    assert validate_capture(path) == []
    capture = read_capture(path)
    header = expected_header(listing)
    actual = {"format": "lpnn.capture", "version": 1, "point_count": capture.point_count, "schema": capture.schema,
              "feature_names": capture.feature_names, "cell_size": capture.cell_size, "units": capture.units,
              "lighting_scale": capture.lighting_scale, "sh_convention": "unity.SphericalHarmonicsL2",
              "label_source": capture.label_source, "source": capture.source}
    for key, value in header.items():
        assert actual[key] == value, key
    assert capture.extra_header == listing.get("extra_header", {})  # unknown header keys are kept
    extras = {key[len("extra_section_"):]: value for key, value in listing.items() if key.startswith("extra_section_")}
    assert extras and sorted(capture.extra_sections) == sorted(extras)
    for name, values in extras.items():
        section = capture.extra_sections[name]
        assert np.array_equal(section, np.asarray(values, dtype=section.dtype).reshape(section.shape)), name
    for name, dtype in (("ids", np.int32), ("positions", np.float32), ("sh", np.float32), ("features", np.float32),
                        ("labels", np.uint8)):
        expected = np.asarray(listing[name], dtype=dtype)
        actual_array = getattr(capture, name)
        assert np.array_equal(actual_array, expected.reshape(actual_array.shape)), name


def test_python_writer_reproduces_the_csharp_bytes(golden_path):
    path = golden_path("capture_golden.lpnncap")
    assert encode_capture(read_capture(path)) == path.read_bytes()
