"""Support for wgputrace's tests and benchmarks (as numpy.testing or Mitsuba's mi.chi2 are for
theirs): nothing else in wgputrace imports it, and it needs the `test` extra (scipy, hypothesis;
python-xlib for the X driver). One concept per module, named for it: statistics (stats,
image_statistics), Mitsuba references (reference_cases, references), ray oracles (oracles), the
WGSL harness and what runs through it (harness, traversal, bsdf_grid), test scenes and files
(scenes, gltf_files, meshopt_files, ktx2_files), fuzzing settings and what a fuzzed file may load
to (fuzzing, fuzz_loading), the viewer's drivers (display, xdriver, running_app,
offscreen_viewer), a call's peak memory (memory) and the source checkout's files (checkout).
"""
