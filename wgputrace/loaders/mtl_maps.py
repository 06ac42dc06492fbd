"""MTL texture maps: the `map_*`, `bump` and `norm` statements of an MTL material, their options,
and the textures of the Principled material they make (the mapping: the OBJ reader's `_mapping`).

A statement is `map_Kd [options] file`; the file is resolved beside the .mtl (backslashes read as
slashes, as Windows exporters write them). Options read: `-clamp on` (clamp both axes, else
repeat), `-bm s` (a normal map's scale). The others (-blendu, -blendv, -boost, -cc, -imfchan, -mm,
-o, -s, -t, -texres, -type) are skipped with their arguments. Single-channel maps (map_Pr,
map_Pm, map_d) read the image's first channel; where two of them share a texture (map_Pr and
map_Pm as G and B, map_d as map_Kd's alpha) the second is resampled (nearest) to the first's size.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..scene.texture import Texture
from .errors import SceneLoadError
from .textures import ImageError, decode_image

# the statements read, each under the name it is kept by (bump, map_bump and norm are one)
MAP_KEYS = {
    **{key: key for key in ("map_kd", "map_ks", "map_pr", "map_pm", "map_ke", "map_d", "bump")},
    "map_bump": "bump",
    "norm": "bump",
}
# the maps that make a material Principled (map_Ks has no Principled parameter and is ignored)
PRINCIPLED_MAPS = ("map_kd", "map_pr", "map_pm", "map_ke", "map_d", "bump")
# option -> (fewest, most) arguments: one each, but -mm's two and -o, -s and -t's 1 to 3 numbers
OPTION_ARGUMENTS = {
    **dict.fromkeys(("-blendu", "-blendv", "-bm", "-boost", "-cc", "-clamp", "-imfchan", "-texres", "-type"), (1, 1)),
    "-mm": (2, 2),
    **dict.fromkeys(("-o", "-s", "-t"), (1, 3)),
}
OPAQUE = 255


@dataclass
class TextureMap:
    statement: str  # as written, for errors
    file: Path
    options: dict[str, list[str]]
    line: int

    def fail(self, mtl_path: Path, problem: str) -> SceneLoadError:
        return SceneLoadError(mtl_path, f"{self.statement} {self.file}: {problem}", self.line)


def parse_map(mtl_path: Path, number: int, tokens: list[str]) -> TextureMap:
    """A map statement's options and file (resolved beside the .mtl)."""
    options: dict[str, list[str]] = {}
    position = 1
    while position < len(tokens) - 1 and tokens[position].lower() in OPTION_ARGUMENTS:
        option = tokens[position].lower()
        fewest, most = OPTION_ARGUMENTS[option]
        end = position + 1 + fewest
        while end - position - 1 < most and end < len(tokens) - 1 and _is_number(tokens[end]):
            end += 1
        options[option] = tokens[position + 1 : end]
        position = end
    name = " ".join(tokens[position:]).replace("\\", "/")
    if not name:
        raise SceneLoadError(mtl_path, f"{tokens[0]} names no image file", number)
    return TextureMap(tokens[0], mtl_path.parent / name, options, number)


def _is_number(token: str) -> bool:
    try:
        float(token)
    except ValueError:
        return False
    return True


class MapImages:
    """The images of one MTL file's maps, each file decoded once."""

    def __init__(self, mtl_path: Path) -> None:
        self.mtl_path = mtl_path
        self._pixels: dict[Path, np.ndarray] = {}

    def pixels(self, texture_map: TextureMap) -> np.ndarray:
        file = texture_map.file
        if file not in self._pixels:
            try:
                data = file.read_bytes()
            except OSError as error:
                raise texture_map.fail(self.mtl_path, f"cannot read the image: {error.strerror or error}") from None
            try:
                self._pixels[file] = decode_image(data)
            except ImageError as error:
                raise texture_map.fail(self.mtl_path, str(error)) from None
        return self._pixels[file]

    def channel(self, texture_map: TextureMap, shape: tuple[int, int] | None = None) -> np.ndarray:
        """The map's first channel as uint8 (H, W), resampled (nearest) to `shape` if given."""
        values = self.pixels(texture_map)[:, :, 0]
        if shape is None or values.shape == shape:
            return values
        rows = np.arange(shape[0]) * values.shape[0] // shape[0]
        columns = np.arange(shape[1]) * values.shape[1] // shape[1]
        return values[rows[:, None], columns[None, :]]

    def texture(self, texture_map: TextureMap, pixels: np.ndarray, srgb: bool) -> Texture:
        wrap = "clamp" if texture_map.options.get("-clamp", ["off"])[0].lower() == "on" else "repeat"
        return Texture(pixels, srgb=srgb, wrap_s=wrap, wrap_t=wrap, name=texture_map.file.name)

    def principled_textures(self, maps: dict[str, TextureMap]) -> dict[str, object]:
        """Principled's texture parameters (and normal_scale) for an entry's maps."""
        parameters: dict[str, object] = {}
        color, dissolve = maps.get("map_kd"), maps.get("map_d")
        if color or dissolve:
            base = self.pixels(color) if color else None
            shape = base.shape[:2] if base is not None else self.pixels(dissolve).shape[:2]
            rgba = np.full((*shape, 4), OPAQUE, np.uint8)
            if base is not None:
                rgba[:, :, :3] = base[:, :, :3] if base.shape[2] >= 3 else base[:, :, :1]
                if base.shape[2] in (2, 4):
                    rgba[:, :, 3] = base[:, :, -1]
            if dissolve:
                rgba[:, :, 3] = self.channel(dissolve, shape)
            parameters["base_color_texture"] = self.texture(color or dissolve, rgba, srgb=True)
        roughness, metallic = maps.get("map_pr"), maps.get("map_pm")
        if roughness or metallic:
            first = roughness or metallic
            shape = self.channel(first).shape
            values = np.full((*shape, 3), OPAQUE, np.uint8)
            if roughness:
                values[:, :, 1] = self.channel(roughness)
            if metallic:
                values[:, :, 2] = self.channel(metallic, shape)
            parameters["metallic_roughness_texture"] = self.texture(first, values, srgb=False)
        if "map_ke" in maps:
            parameters["emission_texture"] = self.texture(maps["map_ke"], self.pixels(maps["map_ke"]), srgb=True)
        if "bump" in maps:
            bump = maps["bump"]
            parameters["normal_texture"] = self.texture(bump, self.pixels(bump), srgb=False)
            scale = bump.options.get("-bm")
            if scale:
                if not _is_number(scale[0]):
                    raise bump.fail(self.mtl_path, f"-bm must be a number, got {scale[0]!r}")
                parameters["normal_scale"] = float(scale[0])
        return parameters
