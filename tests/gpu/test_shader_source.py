"""The include mechanism: each file once, cycles and missing files named, compile errors mapped
back to the original file and line."""

from __future__ import annotations

import pytest

from wgputrace.gpu.kernel import ComputeKernel, ShaderCompileError
from wgputrace.gpu.shader_source import ShaderIncludeError, load_shader, shader_root


def write(root, name, text):
    (root / name).write_text(text)


def test_includes_resolve_once_and_keep_origins(tmp_path):
    write(tmp_path, "a.wgsl", '//! include "b.wgsl"\n//! include "c.wgsl"\nfn a() {}\n')
    write(tmp_path, "b.wgsl", '//! include "c.wgsl"\nfn b() {}\n')
    write(tmp_path, "c.wgsl", "fn c() {}\n")
    source = load_shader("a.wgsl", root=tmp_path)
    assert source.text.count("fn c()") == 1
    assert source.text.splitlines() == ["fn c() {}", "fn b() {}", "fn a() {}"]
    assert source.origins == (("c.wgsl", 1), ("b.wgsl", 2), ("a.wgsl", 3))


def test_cycle_is_an_error_naming_the_chain(tmp_path):
    write(tmp_path, "a.wgsl", '//! include "b.wgsl"\n')
    write(tmp_path, "b.wgsl", 'fn b() {}\n//! include "a.wgsl"\n')
    with pytest.raises(ShaderIncludeError, match=r"b\.wgsl:2: include cycle a\.wgsl -> b\.wgsl -> a\.wgsl"):
        load_shader("a.wgsl", root=tmp_path)


def test_missing_include_names_file_and_line(tmp_path):
    write(tmp_path, "a.wgsl", 'fn a() {}\n\n//! include "nothere.wgsl"\n')
    with pytest.raises(ShaderIncludeError, match=r"a\.wgsl:3: included file 'nothere\.wgsl' not found"):
        load_shader("a.wgsl", root=tmp_path)


def test_generated_files_take_part(tmp_path):
    write(tmp_path, "a.wgsl", '//! include "gen.wgsl"\n')
    source = load_shader("a.wgsl", {"gen.wgsl": "const X: u32 = 3u;"}, root=tmp_path)
    assert source.text.strip() == "const X: u32 = 3u;"


def test_compile_error_names_original_file_and_line(gpu_context):
    broken = (
        '//! include "common/constants.wgsl"\n\nfn compute_broken() -> u32 {\n    let x: u32 = PI;\n    return x;\n}\n'
    )
    entry = broken + "@compute @workgroup_size(1)\nfn main() {}\n"
    with pytest.raises(ShaderCompileError, match=r"broken_entry\.wgsl:4:"):
        ComputeKernel(gpu_context, "broken_entry.wgsl", generated={"broken_entry.wgsl": entry})


def test_every_shipped_shader_starts_with_a_comment_line():
    for path in sorted(shader_root().rglob("*.wgsl")):
        first = path.read_text().splitlines()[0]
        assert first.startswith("// "), f"{path.name} must open with a comment saying what it provides"
