"""Everything that touches wgpu: device, struct layouts, buffers, shader loading and pipelines."""
