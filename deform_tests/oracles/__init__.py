"""The oracles of the tests, the benchmarks and the demo, in one place and independent of
the code under test: `mesh`, `fits` and `nurbs` (numpy and scipy only) and `shapes` (OCCT
through FreeCAD: sections, volumes, closed forms)."""
