"""Triangle and tetrahedral meshes: stretch and sweep, measures, regions, simplification, and
the DimensionDrive handle and drive (Date & Onosato)."""
