"""meshoptimizer-compressed glTF bufferViews (EXT_meshopt_compression and its ratified successor
KHR_meshopt_compression), decoded through the `meshopt` package (an independent binding of
meshoptimizer 1.3's codecs), an 80 KB wheel and a core dependency on Python 3.11 and later (it has
no wheel for 3.10); imported on first use, so that the loader says how to get it where it is missing.

A compressed bufferView keeps its own buffer, byteOffset and byteLength as the place of the
uncompressed data (often a fallback buffer without a uri, which holds none); its extension names
the compressed bytes, their element count and stride, the codec (`mode`) and the `filter` undone
after decoding. The decoded bytes stand in for the view's, so accessors and images read them as
they would read any view. The spec's validity rules are checked here, each failure naming the
extension's JSON path.
"""

from __future__ import annotations

from typing import NamedTuple

MESHOPT_EXTENSIONS = ("KHR_meshopt_compression", "EXT_meshopt_compression")
MESHOPT_INSTALL_HINT = "pip install meshopt (Python 3.11 or later)"
MODES = ("ATTRIBUTES", "TRIANGLES", "INDICES")
# The byteStrides a filter's elements may have (None: any the mode allows); COLOR came with KHR_.
FILTER_STRIDES = {"NONE": None, "OCTAHEDRAL": (4, 8), "QUATERNION": (8,), "EXPONENTIAL": None, "COLOR": (4, 8)}
EXTENSION_FILTERS = {
    "KHR_meshopt_compression": tuple(FILTER_STRIDES),
    "EXT_meshopt_compression": ("NONE", "OCTAHEDRAL", "QUATERNION", "EXPONENTIAL"),
}
INDEX_STRIDES = (2, 4)
MAX_ATTRIBUTE_STRIDE = 256  # the attribute codec's limit, in bytes of one element
# Bytes out per compressed byte beyond which a block is refused before anything is allocated: the
# codecs reach 1024 at most (the attribute codec's version 1 on constant 4-byte elements).
MAX_EXPANSION = 2048


class MeshoptMissing(ImportError):
    """The meshopt package is not installed: the message says how to install it."""


class MeshoptDecodeError(ValueError):
    """Compressed bytes that do not decode to the elements their extension promises."""


class CompressedView(NamedTuple):
    """A bufferView's meshopt extension, checked: where its compressed bytes are and how to decode them."""

    extension: str
    where: str  # its JSON path, bufferViews[i].extensions.<extension>
    buffer: int
    byte_offset: int
    byte_length: int
    stride: int
    count: int
    mode: str
    filter: str


def meshopt_available() -> bool:
    try:
        import meshopt  # noqa: F401
    except ImportError:
        return False
    return True


def meshopt_extension(entry: dict) -> str | None:
    """Which meshopt extension a bufferView or buffer entry carries (KHR_ before EXT_), or None."""
    extensions = entry.get("extensions")
    if not isinstance(extensions, dict):
        return None
    return next((name for name in MESHOPT_EXTENSIONS if name in extensions), None)


def is_fallback(entry: dict) -> bool:
    """Whether a buffer entry is marked as a meshopt fallback: it stands for the uncompressed data."""
    name = meshopt_extension(entry)
    block = entry["extensions"][name] if name else None
    return isinstance(block, dict) and block.get("fallback") is True


def compressed_view(reader, view: dict, index: int) -> CompressedView | None:
    """bufferView `index`'s (the entry `view`) meshopt extension checked against the spec's rules,
    or None when it has none. `reader` is the glTF reader (its `get` and `fail`)."""
    extension = meshopt_extension(view)
    if extension is None:
        return None
    view_where = f"bufferViews[{index}]"
    block = reader.get(reader.get(view, "extensions", dict, view_where), extension, dict, f"{view_where}.extensions")
    where = f"{view_where}.extensions.{extension}"
    layout = CompressedView(
        extension,
        where,
        reader.get(block, "buffer", int, where),
        reader.get(block, "byteOffset", int, where, 0),
        reader.get(block, "byteLength", int, where),
        reader.get(block, "byteStride", int, where),
        reader.get(block, "count", int, where),
        reader.get(block, "mode", str, where),
        reader.get(block, "filter", str, where, "NONE"),
    )
    if min(layout.byte_offset, layout.byte_length, layout.count) < 0:
        raise reader.fail(
            where,
            f"negative byteOffset, byteLength or count: {layout.byte_offset}, {layout.byte_length}, {layout.count}",
        )
    _check_layout(reader, layout, view, view_where)
    return layout


def _check_layout(reader, layout: CompressedView, view: dict, view_where: str) -> None:
    where, stride, mode, filter_ = layout.where, layout.stride, layout.mode, layout.filter
    if mode not in MODES:
        raise reader.fail(f"{where}.mode", f"must be one of {', '.join(MODES)}, got {mode!r:.40}")
    filters = EXTENSION_FILTERS[layout.extension]
    if filter_ not in filters:
        raise reader.fail(f"{where}.filter", f"must be one of {', '.join(filters)}, got {filter_!r:.40}")
    if mode == "ATTRIBUTES":
        if stride % 4 or not 4 <= stride <= MAX_ATTRIBUTE_STRIDE:
            raise reader.fail(
                f"{where}.byteStride",
                f"must be a multiple of 4 from 4 to {MAX_ATTRIBUTE_STRIDE} in mode {mode}, got {stride}",
            )
        allowed = FILTER_STRIDES[filter_]
        if allowed is not None and stride not in allowed:
            raise reader.fail(
                f"{where}.byteStride", f"must be {' or '.join(map(str, allowed))} with filter {filter_}, got {stride}"
            )
    else:
        if stride not in INDEX_STRIDES:
            raise reader.fail(f"{where}.byteStride", f"must be 2 or 4 in mode {mode}, got {stride}")
        if filter_ != "NONE":
            raise reader.fail(f"{where}.filter", f"must be NONE in mode {mode}, got {filter_!r:.40}")
        if mode == "TRIANGLES" and layout.count % 3:
            raise reader.fail(f"{where}.count", f"must be a multiple of 3 in mode TRIANGLES, got {layout.count}")
    size = stride * layout.count
    if size > MAX_EXPANSION * layout.byte_length:
        raise reader.fail(
            where, f"{layout.byte_length} compressed bytes cannot hold {size} (more than {MAX_EXPANSION} times as many)"
        )
    length = reader.get(view, "byteLength", int, view_where)
    if length != stride * layout.count:
        raise reader.fail(
            where,
            f"byteStride {stride} x count {layout.count} = {stride * layout.count} bytes, but {view_where} "
            f"has byteLength {length}",
        )
    # EXT_ asks the view's own byteStride, where it has one, to be the extension's; KHR_ dropped the rule
    if layout.extension == "EXT_meshopt_compression" and view.get("byteStride", stride) != stride:
        raise reader.fail(where, f"byteStride {stride} differs from {view_where}.byteStride {view['byteStride']!r:.20}")


def decode_view(layout: CompressedView, data: bytes) -> bytes:
    """The uncompressed bytes of a view: `layout.count` elements of `layout.stride` bytes, decoded
    from `data` (its compressed bytes). Raises MeshoptMissing, or MeshoptDecodeError."""
    try:
        import meshopt
    except ImportError:
        raise MeshoptMissing(f"{layout.extension} needs the meshopt package: {MESHOPT_INSTALL_HINT}") from None
    if layout.count == 0:  # the library refuses an empty stream; nothing is there to decode
        return b""
    try:
        decoded = meshopt.decode_gltf_buffer(bytes(data), layout.count, layout.stride, layout.mode, layout.filter)
    except ValueError as error:  # "Malformed buffer data: <meshoptimizer's error code>"
        raise MeshoptDecodeError(
            f"its {len(data)} bytes do not decode to {layout.count} elements of {layout.stride} bytes "
            f"in mode {layout.mode} (truncated or corrupt?): {error}"
        ) from None
    return decoded.tobytes()
