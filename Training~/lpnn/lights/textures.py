"""Albedo per shader from the level's textures: shader name -> `name.tga` / `.jpg` / `.png` in the pk3s.

Quake III looks an image up as given, then with .jpg (tr_image.c R_FindImageFile); pk3s later in
alphabetical order override earlier ones (the engine searches them in reverse order). Images are
decoded with Pillow and box-filtered down to at most ALBEDO_SIDE texels a side: the target samples
a triangle at a few points only, so a prefiltered image avoids aliasing on the texture's detail.

Fallback (Documentation~/lights.md §1): a shader without a plain image (defined by a .shader
script only, animated, or missing) takes the mean colour of the level's textures that were found,
or FALLBACK_GREY when none was found (e.g. no texture pak installed). Texture colours are used as
stored (the engine multiplies them with the lightmap in the same way, without linearisation).
"""

from __future__ import annotations

import io
import zipfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np

IMAGE_EXTENSIONS = (".tga", ".jpg", ".png")
ALBEDO_SIDE = 32
FALLBACK_GREY = 0.5


@dataclass(frozen=True)
class Albedo:
    images: list[np.ndarray | None]  # per shader: (h, w, 3) float64 in [0, 1], or None (fallback)
    fallback: np.ndarray  # (3,) colour of shaders without an image
    sources: list[str]  # per shader: "pak:member", or the reason it fell back

    @property
    def found(self) -> int:
        return sum(image is not None for image in self.images)

    def sample(self, shader: np.ndarray, st: np.ndarray) -> np.ndarray:
        """Colour (N, 3) at texture coordinates st (N, 2) of the given shaders (nearest texel, wrapping)."""
        shader = np.asarray(shader, dtype=np.int64)
        out = np.tile(self.fallback, (len(shader), 1))
        for index in np.unique(shader):  # one pass per shader, vectorised over its points
            image = self.images[int(index)]
            if image is None:
                continue
            mask = shader == index
            h, w = image.shape[:2]
            column = np.floor(np.mod(st[mask, 0], 1.0) * w).astype(np.int64) % w
            row = np.floor(np.mod(st[mask, 1], 1.0) * h).astype(np.int64) % h
            out[mask] = image[row, column]
        return out


def texture_paks(level_pak: Path | None, default_folder: Path) -> list[Path]:
    """The pk3s beside the level's pak (or in the default pak's folder for a loose .bsp), sorted."""
    folder = level_pak.parent if level_pak is not None else default_folder
    return sorted(folder.glob("*.pk3")) if folder.is_dir() else []


def uniform_albedo(shader_count: int, grey: float = FALLBACK_GREY) -> Albedo:
    return Albedo(images=[None] * shader_count, fallback=np.full(3, grey), sources=["no textures used"] * shader_count)


def load_albedo(shader_names: list[str], paks: list[Path]) -> Albedo:
    index: dict[str, tuple[Path, str]] = {}
    for pak in paks:  # later paks override earlier ones
        try:
            with zipfile.ZipFile(pak) as archive:
                for member in archive.namelist():
                    lower = member.lower()
                    if lower.endswith(IMAGE_EXTENSIONS):
                        index[lower] = (pak, member)
        except (zipfile.BadZipFile, OSError):
            continue  # an unreadable neighbour pak is not this level's problem; its shaders fall back
    images: list[np.ndarray | None] = []
    sources: list[str] = []
    open_paks: dict[Path, zipfile.ZipFile] = {}
    try:
        for name in shader_names:
            hit = next((index[name.lower() + ext] for ext in IMAGE_EXTENSIONS if name.lower() + ext in index), None)
            if hit is None:
                images.append(None)
                sources.append("fallback: no plain image")
                continue
            pak, member = hit
            archive = open_paks.setdefault(pak, zipfile.ZipFile(pak))
            try:
                images.append(_decode(archive.read(member)))
                sources.append(f"{pak.name}:{member}")
            except (OSError, ValueError, zipfile.BadZipFile) as exc:
                images.append(None)
                sources.append(f"fallback: {member} cannot be decoded ({exc})")
    finally:
        for archive in open_paks.values():
            archive.close()
    means = [image.reshape(-1, 3).mean(axis=0) for image in images if image is not None]
    fallback = np.mean(means, axis=0) if means else np.full(3, FALLBACK_GREY)
    return Albedo(images=images, fallback=fallback, sources=sources)


def _decode(data: bytes) -> np.ndarray:
    from PIL import Image  # Pillow: decodes TGA / JPEG / PNG

    with Image.open(io.BytesIO(data)) as image:
        rgb = image.convert("RGB")
        rgb.load()
    w, h = rgb.size
    if w < 1 or h < 1:
        raise ValueError(f"empty image {w}x{h}")
    reduce_by = max(1, -(-max(w, h) // ALBEDO_SIDE))
    if reduce_by > 1:
        rgb = rgb.reduce(reduce_by)  # box filter
    return np.asarray(rgb, dtype=np.float64) / 255.0
