"""Document objects: one module per feature, each a FeaturePython proxy (no GUI imports)."""
