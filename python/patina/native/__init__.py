"""The compiled C++ engine, `patina.native._core` (nanobind; python/bindings/): tables and their
coherent evaluation, the fitting kernels, the kd-tree tracer and the renderer. Every other
module reaches C++ through it; it imports nothing of the package."""
