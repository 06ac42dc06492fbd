"""glTF materials: pbrMetallicRoughness and its extensions mapped to wgputrace materials (the
tables: `GltfMaterials._mapped`), their textures decoded (images in a .glb's buffer views, base64
data URIs, or files beside the .gltf).

A texture's `sampler` gives its wrap modes (WRAP_MODES, default repeat; its filters are ignored:
textures are sampled bilinearly), `KHR_texture_transform` its offset, rotation and scale. A texture
whose only source is KHR_texture_basisu's reads that KTX2 image where opengl-basisu imports
(`ktx2_images`); one with only a WebP or DDS source, or a KTX2 one without it, is refused by name,
saying how to get it. An image that is missing, unreadable, corrupt, or 0 or over 65,536 pixels a
side is a SceneLoadError naming the file, the JSON path and the problem.
"""

from __future__ import annotations

import base64
import binascii
import urllib.parse
import warnings

from ..scene import Diffuse, Emitter, Glossy, Material, MaterialError, Principled, SceneError
from ..scene.materials.material import ALPHA_MODES
from ..scene.texture import Texture, TextureTransform
from .errors import SceneLoadWarning
from .gltf_anisotropy import AnisotropyReader
from .gltf_material_lobes import lobe_parameters
from .gltf_specular_glossiness import SPECULAR_GLOSSINESS, converted_material
from .gltf_volume import volume_parameters
from .ktx2_images import BASISU_EXTENSION, KTX2_INSTALL_HINT, ktx2_available
from .textures import ImageError, decode_image

DEFAULT_DIFFUSE = 0.8
DEFAULT_IOR = 1.5  # KHR_materials_ior's default
# We have no blends of lobes: a factor from this value up picks the lobe.
LOBE_THRESHOLD = 0.5
DEFAULT_ALPHA_CUTOFF = 0.5
WRAP_MODES = {10497: "repeat", 33071: "clamp", 33648: "mirror"}
TRANSFORM_EXTENSION = "KHR_texture_transform"
# Texture sources in extensions we cannot decode, and what they are
IMAGE_EXTENSIONS = {BASISU_EXTENSION: "KTX2/BasisU", "EXT_texture_webp": "WebP", "MSFT_texture_dds": "DDS"}
# the texture slots of a material: (JSON path below the material, Principled parameter, sRGB colour)
TEXTURE_SLOTS = (
    ("pbrMetallicRoughness.baseColorTexture", "base_color_texture", True),
    ("pbrMetallicRoughness.metallicRoughnessTexture", "metallic_roughness_texture", False),
    ("normalTexture", "normal_texture", False),
    ("emissiveTexture", "emission_texture", True),
)


class GltfMaterials:
    """The materials of one glTF file, each mapped once, and the textures they share."""

    def __init__(self, reader) -> None:
        # the glTF reader's `_Reader` of the file (not imported: its module imports this one)
        self.reader = reader
        self._materials: dict[int | None, Material] = {}
        self._textures: dict[tuple, Texture] = {}
        self._pixels: dict[int, object] = {}
        # whether a material was converted from specular-glossiness (and the file warned of it)
        self._converted = False
        self._anisotropy = AnisotropyReader(reader)

    def material(self, index, where: str) -> Material:
        """The material a primitive at `where` names by `index` (None: it names none)."""
        if index is not None and (not isinstance(index, int) or isinstance(index, bool)):
            raise self.reader.fail(f"{where}.material", f"must be a material index, got {index!r:.40}")
        if index not in self._materials:
            self._materials[index] = self._mapped(index, where)
        return self._materials[index]

    def _mapped(self, index, where: str) -> Material:
        """The wgputrace material for glTF material `index`. One with any texture, alphaMode MASK or
        BLEND, or transmission becomes a Principled (Mitsuba 3's `principled`, after which glTF's model
        was built), every texture read, so an emissive texture lights its triangles as the texture says:

        | glTF field                                                   | Principled parameter |
        |--------------------------------------------------------------|----------------------|
        | `pbrMetallicRoughness.baseColorFactor` (default 1, 1, 1, 1)   | base_color = rgb, alpha = a (1 for alphaMode OPAQUE, which ignores alpha) |
        | `pbrMetallicRoughness.baseColorTexture` (sRGB)               | base_color_texture (RGB x base_color, A x alpha) |
        | `pbrMetallicRoughness.metallicFactor`, `roughnessFactor` (default 1) | metallic, roughness (perceptual, as Principled's) |
        | `pbrMetallicRoughness.metallicRoughnessTexture` (linear)     | metallic_roughness_texture (G x roughness, B x metallic) |
        | `normalTexture` (linear, tangent space), its `scale`          | normal_texture, normal_scale |
        | `emissiveFactor`, `emissiveTexture` (sRGB)                   | emission, emission_texture |
        | `KHR_materials_emissive_strength.emissiveStrength`            | emission_strength |
        | `KHR_materials_ior.ior` (default 1.5)                         | eta |
        | `KHR_materials_transmission.transmissionFactor` (default 0)   | spec_trans (rough dielectric transmission, glTF's roughness) |
        | `KHR_materials_volume` `attenuationColor`, `attenuationDistance` (with transmission) | attenuation_color, attenuation_distance (`volume_parameters`) |
        | `alphaMode`, `alphaCutoff` (default 0.5), `doubleSided` (default false) | alpha_mode, alpha_cutoff, double_sided |
        | `KHR_materials_clearcoat`, `KHR_materials_sheen` (a factor above 0 makes a Principled) | clearcoat, clearcoat_gloss, sheen (`gltf_material_lobes`) |
        | `KHR_materials_anisotropy` (a strength above 0 makes a Principled) | anisotropic, anisotropy_rotation (`gltf_anisotropy`) |

        A material with `KHR_materials_pbrSpecularGlossiness` is converted to metallic-roughness first
        (`gltf_specular_glossiness`). Ignored: `occlusionTexture` (the path tracer computes occlusion), a `texCoord` other than 0 and
        `transmissionTexture` (both with a warning). Any other material (the first rule that applies):

        | glTF material                                                          | wgputrace material |
        |------------------------------------------------------------------------|--------------------|
        | `emissiveFactor` x `KHR_materials_emissive_strength.emissiveStrength` > 0 | Emitter: color = emissiveFactor, emittance = emissiveStrength (default 1) |
        | `pbrMetallicRoughness.metallicFactor` (default 1) >= 0.5               | Glossy: color = baseColorFactor rgb, roughness = roughnessFactor^2 (glTF's roughness is perceptual; GGX alpha is its square) |
        | anything else                                                          | Diffuse: color = baseColorFactor rgb |
        | a primitive without a material                                         | Diffuse: grey 0.8 (not glTF's default, which is a rough metal) |
        """
        reader = self.reader
        if index is None:
            return Diffuse("default", color=(DEFAULT_DIFFUSE,) * 3)
        entry = reader.item("materials", index, f"{where}.material")
        where = f"materials[{index}]"
        if SPECULAR_GLOSSINESS in reader.get(entry, "extensions", dict, where, {}):
            entry = converted_material(reader, entry, where, self._converted)
            self._converted = True
        name = entry.get("name") if isinstance(entry.get("name"), str) else f"material{index}"
        pbr = reader.get(entry, "pbrMetallicRoughness", dict, where, {})
        pbr_where = f"{where}.pbrMetallicRoughness"
        base = reader.numbers(pbr, "baseColorFactor", 4, pbr_where, [1.0, 1.0, 1.0, 1.0])
        metallic = reader.get(pbr, "metallicFactor", float, pbr_where, 1.0)
        roughness = reader.get(pbr, "roughnessFactor", float, pbr_where, 1.0)
        emissive = reader.numbers(entry, "emissiveFactor", 3, where, [0.0, 0.0, 0.0])
        extensions = reader.get(entry, "extensions", dict, where, {})

        def extension(name: str, key: str, default: float) -> float:
            block = reader.get(extensions, name, dict, f"{where}.extensions", {})
            return reader.get(block, key, float, f"{where}.extensions.{name}", default)

        strength = extension("KHR_materials_emissive_strength", "emissiveStrength", 1.0)
        transmission = extension("KHR_materials_transmission", "transmissionFactor", 0.0)
        if "transmissionTexture" in extensions.get("KHR_materials_transmission", {}):
            warnings.warn(
                f"{reader.path}: {where}.extensions.KHR_materials_transmission.transmissionTexture: "
                f"spec_trans takes no texture; transmissionFactor {transmission} is used alone",
                SceneLoadWarning,
                stacklevel=6,
            )
        ior = extension("KHR_materials_ior", "ior", DEFAULT_IOR)
        alpha_mode = reader.get(entry, "alphaMode", str, where, "OPAQUE")
        if alpha_mode not in ALPHA_MODES:
            raise reader.fail(f"{where}.alphaMode", f"must be one of {ALPHA_MODES}, got {alpha_mode!r:.40}")
        slots = [(path, parameter, srgb) for path, parameter, srgb in TEXTURE_SLOTS if _info(entry, path) is not None]
        lobes = lobe_parameters(reader, extensions, f"{where}.extensions")
        lobes |= self._anisotropy.parameters(extensions, roughness, f"{where}.extensions")
        try:
            if slots or alpha_mode != "OPAQUE" or transmission > 0 or max(lobes.values(), default=0.0) > 0:
                parameters = {parameter: self._texture(entry, path, srgb, where) for path, parameter, srgb in slots}
                parameters |= self._set_values(entry, where, emissive, strength, alpha_mode)
                if transmission > 0:
                    parameters |= volume_parameters(reader, extensions, where)
                return Principled(
                    name,
                    base_color=tuple(base[:3]),
                    alpha=float(base[3]) if alpha_mode != "OPAQUE" else 1.0,  # OPAQUE ignores alpha
                    metallic=metallic,
                    roughness=roughness,
                    eta=ior,
                    spec_trans=transmission,
                    **parameters,
                    **lobes,
                )
            if emissive.max() * strength > 0:
                return Emitter(name, color=emissive.tolist(), emittance=strength)
            if metallic >= LOBE_THRESHOLD:
                return Glossy(name, color=base[:3].tolist(), roughness=roughness * roughness)
            return Diffuse(name, color=base[:3].tolist())
        except (MaterialError, SceneError) as error:
            raise reader.fail(where, str(error)) from None

    def _set_values(self, entry: dict, where: str, emissive, strength: float, alpha_mode: str) -> dict:
        """Principled's emission, normal map scale, alpha mode and sidedness where the file sets them."""
        reader = self.reader
        values: dict[str, object] = {"double_sided": reader.get(entry, "doubleSided", bool, where, False)}
        if emissive.max() > 0:
            values |= {"emission": tuple(emissive.tolist()), "emission_strength": strength}
        if "normalTexture" in entry:
            values["normal_scale"] = reader.get(entry["normalTexture"], "scale", float, f"{where}.normalTexture", 1.0)
        if alpha_mode != "OPAQUE":
            values["alpha_mode"] = alpha_mode
        if alpha_mode == "MASK":
            values["alpha_cutoff"] = reader.get(entry, "alphaCutoff", float, where, DEFAULT_ALPHA_CUTOFF)
        return values

    def _texture(self, material: dict, path: str, srgb: bool, material_where: str) -> Texture:
        """The Texture the textureInfo at `path` in `material` names."""
        reader = self.reader
        where = f"{material_where}.{path}"
        info = _info(material, path)
        if not isinstance(info, dict):
            raise reader.fail(where, f"must be an object (a textureInfo), got {info!r:.40}")
        index = reader.get(info, "index", int, where)
        if reader.get(info, "texCoord", int, where, 0) != 0:
            warnings.warn(
                f"{reader.path}: {where}.texCoord: only TEXCOORD_0 is read; this texture uses it instead",
                SceneLoadWarning,
                stacklevel=7,
            )
        transform = self._transform(info, where)
        entry = reader.item("textures", index, f"{where}.index")
        texture_where = f"textures[{index}]"
        sampler: dict = {}
        if "sampler" in entry:
            sampler = reader.item("samplers", entry["sampler"], f"{texture_where}.sampler")
        wraps = []
        for axis in ("wrapS", "wrapT"):
            code = reader.get(sampler, axis, int, f"samplers[{entry.get('sampler')}]", 10497)
            if code not in WRAP_MODES:
                raise reader.fail(f"samplers[{entry['sampler']}].{axis}", f"must be 10497, 33071 or 33648, got {code}")
            wraps.append(WRAP_MODES[code])
        source, source_where = self._source(entry, texture_where)
        key = (source, srgb, *wraps, transform)
        if key not in self._textures:
            image_name = reader.item("images", source, source_where).get("name")
            name = image_name if isinstance(image_name, str) else f"image{source}"
            try:
                self._textures[key] = Texture(
                    self._image(source, source_where),
                    srgb=srgb,
                    wrap_s=wraps[0],
                    wrap_t=wraps[1],
                    name=name,
                    transform=transform,
                )
            except SceneError as error:
                raise reader.fail(f"images[{source}]", str(error)) from None
        return self._textures[key]

    def _transform(self, info: dict, where: str) -> TextureTransform:
        reader = self.reader
        extensions = reader.get(info, "extensions", dict, where, {})
        if TRANSFORM_EXTENSION not in extensions:
            return TextureTransform()
        block = reader.get(extensions, TRANSFORM_EXTENSION, dict, f"{where}.extensions")
        where = f"{where}.extensions.{TRANSFORM_EXTENSION}"
        if reader.get(block, "texCoord", int, where, 0) != 0:
            warnings.warn(
                f"{reader.path}: {where}.texCoord: only TEXCOORD_0 is read; this texture uses it instead",
                SceneLoadWarning,
                stacklevel=8,
            )
        return TextureTransform(
            offset=tuple(reader.numbers(block, "offset", 2, where, [0.0, 0.0]).tolist()),
            rotation=reader.get(block, "rotation", float, where, 0.0),
            scale=tuple(reader.numbers(block, "scale", 2, where, [1.0, 1.0]).tolist()),
        )

    def _source(self, texture: dict, where: str) -> tuple[int, str]:
        """The image index of a texture and the JSON path that gives it (its own `source`, a PNG or
        JPEG fallback where it has one, else KHR_texture_basisu's), or the refusal of a source
        only an extension we cannot decode gives."""
        reader = self.reader
        if "source" in texture:
            return reader.get(texture, "source", int, where), f"{where}.source"
        extensions = reader.get(texture, "extensions", dict, where, {})
        if BASISU_EXTENSION in extensions and ktx2_available():
            block = reader.get(extensions, BASISU_EXTENSION, dict, f"{where}.extensions")
            block_where = f"{where}.extensions.{BASISU_EXTENSION}"
            return reader.get(block, "source", int, block_where), f"{block_where}.source"
        named = [f"{name} ({IMAGE_EXTENSIONS[name]})" for name in extensions if name in IMAGE_EXTENSIONS]
        if named:
            hint = f" (KTX2 needs opengl-basisu: {KTX2_INSTALL_HINT})" if BASISU_EXTENSION in extensions else ""
            raise reader.fail(where, f"its image is only given as {', '.join(named)}, which is not decoded here{hint}")
        raise reader.fail(where, "'source' is missing")

    def _image(self, index: int, where: str):
        """Image `index`'s pixels, decoded once however many textures use it."""
        if index not in self._pixels:
            reader = self.reader
            entry = reader.item("images", index, where)
            where = f"images[{index}]"
            if "bufferView" in entry:
                data, _ = reader.view(entry["bufferView"], f"{where}.bufferView")
                origin = f"{where}.bufferView"
            else:
                data, origin = self._uri_bytes(entry, where)
            try:
                self._pixels[index] = decode_image(bytes(data))
            except ImageError as error:
                raise reader.fail(origin, str(error)) from None
        return self._pixels[index]

    def _uri_bytes(self, image: dict, where: str) -> tuple[bytes, str]:
        """The bytes of an image given by `uri` (a data URI, or a file beside the glTF), and the
        field to name in an error about them (the file, where there is one)."""
        reader = self.reader
        uri = reader.get(image, "uri", str, where)
        if uri.startswith("data:"):
            try:
                return base64.b64decode(uri.split(",", 1)[1], validate=True), f"{where}.uri"
            except (IndexError, binascii.Error, ValueError) as error:
                raise reader.fail(f"{where}.uri", f"data URI does not decode: {error}") from None
        file = reader.path.parent / urllib.parse.unquote(uri)
        try:
            return file.read_bytes(), f"{where}.uri ({file})"
        except OSError as error:
            raise reader.fail(f"{where}.uri", f"cannot read {file}: {error.strerror or error}") from None


def _info(material: dict, path: str):
    """The value at a dotted `path` below `material`, or None where any step is absent."""
    node = material
    for key in path.split("."):
        if not isinstance(node, dict):
            return None
        node = node.get(key)
    return node
