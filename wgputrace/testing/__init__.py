"""Support for wgputrace's tests and benchmarks (as numpy.testing or Mitsuba's mi.chi2 are for
theirs): nothing else in wgputrace imports it, and it needs the `test` extra (scipy, hypothesis;
python-xlib for the X driver). One concept per module:

- stats: Sidak-corrected levels, z limits, Pearson's chi-square with pooling, binomial tests,
  the power a sample count buys, histogram images.
- image_statistics: Monte Carlo images as estimates with variances; Welch's test per block,
  z-scores of two images' difference per block.
- reference_cases: every comparison with a Mitsuba 3 reference (the tests' cases) and how Mitsuba
  renders each reference (scripts/make_references.py).
- references: the Mitsuba 3 reference images of tests/references/, batched renders of ours,
  images and lines describing a failed comparison.
- oracles: float64 numpy ray oracles (Moller-Trumbore, slabs, brute-force and BVH closest hits,
  from-scratch BVH bounds) and the record packing both sides of a shader comparison share.
- scenes: small scenes with closed-form images, random triangle soups and rays, a deep BVH case.
- bsdf_grid: the shipped BSDFs run on the GPU and integrated over hemisphere grids.
- gltf_files: small glTF/GLB files written from numpy arrays.
- fuzzing: Hypothesis settings of the property-based tests, a per-example time limit.
- display: a virtual X display (Xvfb) for windows without a screen.
- xdriver: keys, mouse and pixels of a real X window, through XTEST.
- running_app: the viewer started as a person starts it, in its own process.
- checkout: files of the source checkout (reference images, app.py), with a clear error outside one.
- harness: a WGSL harness kernel running shipped shader functions on numpy arrays.
"""
