"""The deformation pipelines: Part/Mesh/Points and plain values in, result and output values out; no document objects."""
