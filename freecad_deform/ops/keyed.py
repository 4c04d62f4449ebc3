"""Case 1 by a key-frame motion (Wu & Ilies, Steps 4-7): the part beyond Plane moves along
`motion` (geometry.sweep.motion, M(0) = identity) to M(1), and the gap is the section swept
through the motion's profiles. Stretch and Bend give it their KeyPlacements."""
from ..geometry.mesh import sweep as mesh_sweep
from ..geometry.points import sweep as points_sweep
from ..shapes import brep
from . import planes as pp


def solid(shape, origin, normal, motion, samples=16):
    """(shape, {VolumeChange, Continuity, SplitFaces}): each solid lofted through `samples`
    profiles; loose wires and faces kept or moved with their side."""
    end = motion.matrix(1.0)

    def loose_fn(parts):
        near, far = brep.split_loose(parts, origin, normal, [0.0])
        return near + brep.transformed(far, end)

    result = pp.deform_shape(shape, origin, normal, None,
                             lambda s: pp.sweep_solid(s, origin, normal, motion, samples),
                             loose_fn)
    return result, {**pp.volume_change(result, shape),
                    **pp.joint_report(shape, pp.motion_joints(origin, normal, motion))}


def mesh(base, origin, normal, motion, samples=16):
    """(Mesh, {VolumeChange}): the section ring swept through samples + 1 configurations."""
    from ..shapes.convert import mesh_arrays, mesh_eps
    v, t = mesh_arrays(base)
    return pp.mesh_result((v, t), *mesh_sweep.sweep_mesh(v, t, origin, normal, motion, samples,
                                                        mesh_eps(v)))


def points(base, origin, normal, motion):
    """(Points, {IgnoredPoints}): the far points moved, the gap filled at the cloud's
    spacing."""
    from ..shapes.convert import points_from_array
    pts, ignored = pp.cloud(base)
    return points_from_array(points_sweep.sweep_points(pts, origin, normal, motion,
                                                       prop="KeyPlacements")), ignored
