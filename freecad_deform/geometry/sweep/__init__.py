"""Split-sweep-join kinematics (Wu & Ilies): planes, motions, space maps, bend checks, joint continuity."""
