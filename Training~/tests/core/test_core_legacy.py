"""The thesis' features.txt / comparisons.txt reader and converter (Documentation~/file-formats.md)."""

from __future__ import annotations

import numpy as np
import pytest

from lpnn.core.capture_file import read_capture, write_capture
from lpnn.core.legacy import LegacyFormatError, legacy_to_capture, read_legacy_features, read_legacy_labels
from lpnn.core.schema import THESIS30


def thesis_block(first: float, greek: bool = True) -> str:
    """30 values over 3 lines, as the thesis wrote them (Greek locale: decimal commas)."""
    values = [first] + [0.5 * v for v in range(1, 30)]
    text = [f"{v:.7G}".replace(".", ",") if greek else f"{v:.7G}" for v in values]
    return "\n".join(" ".join(text[i:i + 10]) for i in range(0, 30, 10))


def write(path, text: str, newline: str = "\n"):
    path.write_bytes(text.replace("\n", newline).encode("utf-8"))
    return path


def test_greek_decimal_commas_exponents_and_blank_line_runs(tmp_path):
    text = "30\n\n" + thesis_block(0.0226) + "\n\n\n  \n" + thesis_block(2.338238e-05) + "\n\n" + thesis_block(-1.5, False) + "\n"
    legacy = read_legacy_features(write(tmp_path / "features.txt", text, newline="\r\n"))
    assert legacy.values.shape == (3, 30)
    assert legacy.values[0, 0] == 0.0226 and legacy.values[1, 0] == 2.338238e-05 and legacy.values[2, 0] == -1.5
    assert legacy.values[1, 29] == 14.5
    assert legacy.first_lines.tolist() == [3, 9, 13]
    tokens = "2,338238E-05 1,5e+3 .5 ,25 -0,0226 +3 7"
    small = read_legacy_features(write(tmp_path / "small.txt", f"7\n{tokens}\n"))
    assert small.values.tolist() == [[2.338238e-05, 1500.0, 0.5, 0.25, -0.0226, 3.0, 7.0]]


def test_anything_after_the_count_on_its_line_is_ignored_like_the_thesis_reader(tmp_path):
    legacy = read_legacy_features(write(tmp_path / "f.txt", "3 values per point\n1,5 2\n3\n\n4 5 6\n"))
    assert legacy.values.tolist() == [[1.5, 2.0, 3.0], [4.0, 5.0, 6.0]]
    assert legacy.first_lines.tolist() == [2, 5]


@pytest.mark.parametrize("text, match", [
    ("3\n1 2 3\n\n4 5\n\n7 8 9\n", r"line 4: the block starting here has 2 values, expected F = 3"),
    ("3\n1 2 3\n4\n", r"line 2: the block starting here has 4 values, expected F = 3"),
    ("3\n1 2 NaN\n", r"line 2: 'NaN' is not a finite decimal number"),
    ("3\n1 2 1,234,5\n", r"line 2: '1,234,5' is not a finite decimal number"),
    ("3\n1 2 1_000\n", r"line 2: '1_000' is not a finite decimal number"),
    ("3\n1 2 1e999\n", r"too large"),
    ("\n\n", r"empty"),
    ("abc\n1 2 3\n", r"line 1: 'abc' is not the feature count"),
    ("3\n\n", r"no feature blocks"),
])
def test_feature_file_errors_name_file_line_and_count(tmp_path, text, match):
    path = write(tmp_path / "features.txt", text)
    with pytest.raises(LegacyFormatError, match=match) as error:
        read_legacy_features(path)
    assert str(path) in str(error.value)


def test_labels(tmp_path):
    labels = read_legacy_labels(write(tmp_path / "c.txt", "True\nfalse\n\n  TRUE  \nFalse\n"))
    assert labels.dtype == np.uint8 and labels.tolist() == [1, 0, 1, 0]
    with pytest.raises(LegacyFormatError, match=r"c2.txt: line 2: 'yes' is not True or False"):
        read_legacy_labels(write(tmp_path / "c2.txt", "True\nyes\n"))


def test_conversion_to_a_thesis30_capture(tmp_path):
    features = write(tmp_path / "features.txt", "30\n" + "\n\n".join(thesis_block(v) for v in (1, 2, 3)) + "\n")
    labels = write(tmp_path / "comparisons.txt", "False\nTrue\nTrue\n")
    capture = legacy_to_capture(features, labels, "office")
    assert capture.schema == THESIS30.id and capture.feature_names == list(THESIS30.names)
    assert capture.ids.tolist() == [[0, 0, 0], [1, 0, 0], [2, 0, 0]]
    assert capture.positions.tolist() == [[0, 0, 0], [1, 0, 0], [2, 0, 0]]
    assert not capture.sh.any() and capture.cell_size == 1.0 and capture.lighting_scale == 1.0
    assert capture.source["legacy"] is True and capture.source["scene"] == "office"
    assert capture.labels.tolist() == [0, 1, 1] and capture.label_source
    again = read_capture(write_capture(tmp_path / "office.lpnncap", capture))
    assert np.array_equal(again.features, capture.features) and again.features[2, 0] == 3.0
    assert legacy_to_capture(features, None, "office").labels is None


def test_conversion_errors(tmp_path):
    features = write(tmp_path / "features.txt", "30\n" + "\n\n".join(thesis_block(v) for v in (1, 2)) + "\n")
    labels = write(tmp_path / "comparisons.txt", "False\nTrue\nTrue\n")
    with pytest.raises(LegacyFormatError, match=r"comparisons.txt: 3 labels, but .*features.txt has 2 feature blocks"):
        legacy_to_capture(features, labels, "s")
    short = write(tmp_path / "short.txt", "2\n1 2\n")
    with pytest.raises(LegacyFormatError, match=r"short.txt: line 2: F = 2 values per point, but .*has 30"):
        legacy_to_capture(short, None, "s")
