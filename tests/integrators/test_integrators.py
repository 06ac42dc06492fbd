"""Integrators are descriptors that the renderer, the command line and the limits ask: the
registry's names and refusals, and what each descriptor says of itself."""

from __future__ import annotations

import pytest

from wgputrace import Renderer, default_scene
from wgputrace.cli_arguments import add_method_arguments
from wgputrace.integrators import Integrator, integrator, integrator_names
from wgputrace.integrators.bdpt import BDPT_MAX_DEPTH
from wgputrace.integrators.integrator import register
from wgputrace.integrators.splats import SPLATS


def test_names_in_order_with_the_path_tracer_first():
    assert integrator_names() == ("bsdf", "nee", "mis", "bdpt", "restir")


def test_an_unknown_name_is_refused_naming_the_choices():
    with pytest.raises(
        ValueError, match=r"integrator must be one of \('bsdf', 'nee', 'mis', 'bdpt', 'restir'\), got 'photon'"
    ):
        integrator("photon")


def test_a_name_registers_once():
    with pytest.raises(ValueError, match="an integrator named 'mis' is already registered"):
        register(Integrator("mis", "integrators/path_tracer.wgsl", "again"))


def test_descriptors_say_what_they_need():
    mis, bdpt = integrator("mis"), integrator("bdpt")
    assert mis.rows_entry is not None and not mis.splats and mis.pixel_arrays == ()
    assert bdpt.rows_entry is None and bdpt.splats and bdpt.pixel_arrays == (SPLATS,)
    mis.check_depth(-1)
    with pytest.raises(ValueError, match=f"integrator 'bdpt' takes max_depth from 1 to {BDPT_MAX_DEPTH}, got -1"):
        bdpt.check_depth(-1)


def test_the_command_line_offers_every_integrator():
    import argparse

    parser = argparse.ArgumentParser()
    add_method_arguments(parser)
    choices = next(action.choices for action in parser._actions if action.dest == "integrator")
    assert tuple(choices) == integrator_names()


@pytest.mark.gpu
def test_the_renderer_allocates_what_the_descriptor_declares(gpu_context):
    for name in integrator_names():
        renderer = Renderer(default_scene(), 8, 8, integrator=name)
        declared = {array.binding.name for array in integrator(name).pixel_arrays}
        assert declared <= set(renderer.gpu_image_bytes)
        assert renderer.integrator is integrator(name)
        assert renderer.variant.integrator is integrator(name)
