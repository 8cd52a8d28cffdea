"""Tests/Data/schema_lpnn.features.v1.json: the feature names and order both languages use."""

from __future__ import annotations

from lpnn.core.features import FEATURE_COUNT
from lpnn.core.schema import LPNN_V1


def test_lpnn_v1_names_equal_the_schema_file(golden):
    data = golden("schema_lpnn.features.v1.json")
    assert data["schema"] == LPNN_V1.id
    assert list(LPNN_V1.names) == data["feature_names"]
    assert data["feature_count"] == LPNN_V1.feature_count == FEATURE_COUNT == 19
