"""Feature schemas (Documentation~/features.md): ids and ordered feature names."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class FeatureSchema:
    id: str
    names: tuple[str, ...]
    extractable: bool

    @property
    def feature_count(self) -> int:
        return len(self.names)


LPNN_V1 = FeatureSchema(
    id="lpnn.features.v1",
    names=(
        "log_luminance",
        "chroma_co",
        "chroma_cg",
        "directionality",
        "light_variance",
        "rgb_variance_r",
        "rgb_variance_g",
        "rgb_variance_b",
        "boundary",
        "change_1",
        "change_2",
        "change_4",
        "curvature_1",
        "curvature_2",
        "curvature_4",
        "occlusion_near",
        "occlusion_far",
        "nearest_surface",
        "normal_spread",
    ),
    extractable=True,
)

THESIS30 = FeatureSchema(
    id="lpnn.thesis30",
    names=tuple(f"sh_d{d}_{c}" for d in range(6) for c in "rgba")
    + ("light_variance", "normal_variance", "occlusion_factor", "rgb_variance_r", "rgb_variance_g", "rgb_variance_b"),
    extractable=False,
)

SCHEMAS: dict[str, FeatureSchema] = {s.id: s for s in (LPNN_V1, THESIS30)}


def schema_by_id(schema_id: str) -> FeatureSchema | None:
    """The known schema with this id, or None for a schema this version does not know."""
    return SCHEMAS.get(schema_id)
