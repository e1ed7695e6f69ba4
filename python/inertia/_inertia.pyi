"""Type stubs of the inertia extension (python/src/*.cpp). Units are SI; quaternions are
[w, x, y, z]; arrays have dtype real_dtype (float32, or float64 in a double build).
python/tests/test_stubs.py checks that these name exactly what the module has."""

from typing import Any, Iterable, Optional, Sequence, Union, overload

import numpy as np
import numpy.typing as npt

Vec3Like = Union[Sequence[float], npt.ArrayLike]
QuatLike = Union[Sequence[float], npt.ArrayLike]
Array = npt.NDArray[Any]

real_dtype: np.dtype[Any]

class InvalidArgument(ValueError):
    """An invalid argument (negative size, NaN, invalid id, ...)."""

class SceneError(ValueError):
    """A problem with a scene: str() reads 'FILE: POINTER: REASON'."""
    file: str
    pointer: str
    """The JSON pointer of the offending value, e.g. '/world/dt'; empty for syntax errors."""
    reason: str

class BodyId:
    index: int
    generation: int
    def __init__(self) -> None: ...
    def is_null(self) -> bool: ...

class ShapeId:
    index: int
    generation: int
    def __init__(self) -> None: ...
    def is_null(self) -> bool: ...

class JointId:
    index: int
    generation: int
    def __init__(self) -> None: ...
    def is_null(self) -> bool: ...

class ParticleSystemId:
    index: int
    generation: int
    def __init__(self) -> None: ...
    def is_null(self) -> bool: ...

class DeformableId:
    index: int
    generation: int
    def __init__(self) -> None: ...
    def is_null(self) -> bool: ...

class ArticulationId:
    index: int
    generation: int
    def __init__(self) -> None: ...
    def is_null(self) -> bool: ...

class BodyType:
    STATIC: BodyType
    KINEMATIC: BodyType
    DYNAMIC: BodyType
    name: str
    value: int

# Shapes and materials.

class Material:
    density: float
    """kg/m^3"""
    friction: float
    dynamic_friction: float
    restitution: float
    rolling_friction: float
    """m"""
    spinning_friction: float
    """m"""
    def __init__(self, *, density: float = 1000, friction: float = 0.6,
                 dynamic_friction: float = -1, restitution: float = 0,
                 rolling_friction: float = 0, spinning_friction: float = 0) -> None: ...

class Sphere:
    radius: float
    def __init__(self, radius: float = 0.5) -> None: ...

class Capsule:
    radius: float
    half_height: float
    def __init__(self, radius: float = 0.5, half_height: float = 0.5) -> None: ...

class Cylinder:
    radius: float
    half_height: float
    def __init__(self, radius: float = 0.5, half_height: float = 0.5) -> None: ...

class Box:
    half_extents: Array
    def __init__(self, half_extents: Vec3Like) -> None: ...

class Plane:
    normal: Array
    offset: float
    def __init__(self, normal: Vec3Like = (0, 1, 0), offset: float = 0) -> None: ...

class ConvexHull:
    vertices: Array
    def __init__(self, points: npt.ArrayLike) -> None: ...

class TriangleMesh:
    is_closed: bool
    def __init__(self, vertices: npt.ArrayLike, triangles: Sequence[Sequence[int]]) -> None: ...

class HeightField:
    def __init__(self, heights: npt.ArrayLike, spacing: float) -> None: ...

Shape = Union[Sphere, Capsule, Cylinder, Box, Plane, ConvexHull, TriangleMesh, HeightField,
              "Compound"]

class Compound:
    def __init__(self, children: list[tuple[Any, ...]]) -> None: ...

# Results of a step.

class WorldState:
    time: float
    step_count: int

class Contact:
    body_a: BodyId
    body_b: BodyId
    shape_a: ShapeId
    shape_b: ShapeId
    normal: Array
    points_a: Array
    points_b: Array
    separations: Array
    normal_impulses: Array

class ContactEvent:
    body_a: BodyId
    body_b: BodyId
    shape_a: ShapeId
    shape_b: ShapeId
    point: Array
    normal: Array
    approach_speed: float

class RayHit:
    body: BodyId
    shape: ShapeId
    distance: float
    point: Array
    normal: Array

class JointEvent:
    joint: JointId
    force: Array
    torque: Array

# Joints.

class JointLimits:
    lower: float
    upper: float
    def __init__(self, lower: float, upper: float) -> None: ...

class JointMotor:
    speed: float
    max_force: float
    target: Optional[float]
    servo_frequency: float
    def __init__(self, *, speed: float = 0, max_force: float = 0,
                 target: Optional[float] = None, servo_frequency: float = 2) -> None: ...

class JointSpring:
    frequency: float
    damping_ratio: float
    rest: float
    def __init__(self, *, frequency: float = 1, damping_ratio: float = 0,
                 rest: float = 0) -> None: ...

LimitsLike = Union[JointLimits, Sequence[float], None]

class JointAxis:
    locked: bool
    limits: Optional[JointLimits]
    motor: Optional[JointMotor]
    spring: Optional[JointSpring]
    friction: float
    def __init__(self, **kwargs: Any) -> None: ...

class BallJoint:
    body_a: Optional[BodyId]
    body_b: Optional[BodyId]
    anchor_a: Array
    anchor_b: Array
    axis_a: Array
    axis_b: Array
    cone_limit: Optional[float]
    twist_limits: Optional[JointLimits]
    friction: float
    break_force: float
    break_torque: float
    collide_connected: bool
    name: str
    def __init__(self, **kwargs: Any) -> None: ...

class HingeJoint:
    body_a: Optional[BodyId]
    body_b: Optional[BodyId]
    anchor_a: Array
    anchor_b: Array
    axis_a: Array
    axis_b: Array
    limits: Optional[JointLimits]
    motor: Optional[JointMotor]
    spring: Optional[JointSpring]
    friction: float
    break_force: float
    break_torque: float
    collide_connected: bool
    name: str
    def __init__(self, **kwargs: Any) -> None: ...

class SliderJoint:
    body_a: Optional[BodyId]
    body_b: Optional[BodyId]
    anchor_a: Array
    anchor_b: Array
    axis_a: Array
    limits: Optional[JointLimits]
    motor: Optional[JointMotor]
    spring: Optional[JointSpring]
    friction: float
    break_force: float
    break_torque: float
    collide_connected: bool
    name: str
    def __init__(self, **kwargs: Any) -> None: ...

class UniversalJoint:
    body_a: Optional[BodyId]
    body_b: Optional[BodyId]
    anchor_a: Array
    anchor_b: Array
    axis_a: Array
    axis_b: Array
    limits_a: Optional[JointLimits]
    limits_b: Optional[JointLimits]
    break_force: float
    break_torque: float
    collide_connected: bool
    name: str
    def __init__(self, **kwargs: Any) -> None: ...

class WeldJoint:
    body_a: Optional[BodyId]
    body_b: Optional[BodyId]
    anchor_a: Array
    anchor_b: Array
    spring: Optional[JointSpring]
    break_force: float
    break_torque: float
    collide_connected: bool
    name: str
    def __init__(self, **kwargs: Any) -> None: ...

class DistanceJoint:
    body_a: Optional[BodyId]
    body_b: Optional[BodyId]
    anchor_a: Array
    anchor_b: Array
    length: float
    min_length: float
    max_length: float
    spring: Optional[JointSpring]
    break_force: float
    break_torque: float
    collide_connected: bool
    name: str
    def __init__(self, **kwargs: Any) -> None: ...

class SixDofJoint:
    body_a: Optional[BodyId]
    body_b: Optional[BodyId]
    frame_a: tuple[Array, Array]
    frame_b: tuple[Array, Array]
    axes: list[JointAxis]
    break_force: float
    break_torque: float
    collide_connected: bool
    name: str
    def __init__(self, **kwargs: Any) -> None: ...

JointSettings = Union[BallJoint, HingeJoint, SliderJoint, UniversalJoint, WeldJoint,
                      DistanceJoint, SixDofJoint]

# Particles.

class Emitter:
    shape: str
    position: Array
    orientation: Array
    radius: float
    half_extents: Array
    angle: float
    mesh: None
    rate: float
    burst: int
    direction: Array
    spread: float
    speed: tuple[float, float]
    lifetime: tuple[float, float]
    mass: tuple[float, float]
    size: tuple[float, float]
    color_min: Array
    color_max: Array
    seed: int
    attach_to: Optional[BodyId]
    def __init__(self, **kwargs: Any) -> None: ...

class GravityField:
    def __init__(self, g: Vec3Like = (0, -9.81, 0)) -> None: ...

class LinearDragField:
    def __init__(self, k: float = 0.1) -> None: ...

class QuadraticDragField:
    def __init__(self, k: float = 0.01) -> None: ...

class WindField:
    def __init__(self, velocity: Vec3Like = (1, 0, 0), k: float = 0.1) -> None: ...

class VortexField:
    def __init__(self, *, center: Vec3Like = (0, 0, 0), axis: Vec3Like = (0, 1, 0),
                 angular_speed: float = 1, core_radius: float = 1,
                 tightness: float = 5) -> None: ...

class AttractorField:
    def __init__(self, *, position: Vec3Like = (0, 0, 0), strength: float = 1,
                 falloff: str = "inverse_square", cutoff: float = ...,
                 min_distance: float = 0.05) -> None: ...

class TurbulenceField:
    def __init__(self, *, amplitude: float = 1, scale: float = 1, speed: float = 0,
                 modes: int = 8, seed: int = 1) -> None: ...

Field = Union[GravityField, LinearDragField, QuadraticDragField, WindField, VortexField,
              AttractorField, TurbulenceField]

# The world.

class World:
    gravity: Array
    dt: float
    substeps: int
    threads: int
    time: float
    step_count: int
    interpolation_alpha: float
    body_count: int
    contact_count: int
    joint_count: int
    def __init__(self, *, gravity: Vec3Like = (0, -9.81, 0), dt: float = 1 / 60,
                 substeps: int = 4, solver: str = "soft_step", iterations: int = 4,
                 relax_iterations: int = 1, joint_hertz: float = 120,
                 joint_damping_ratio: float = 2, integrator: str = "symplectic_euler",
                 threads: int = 0, sleeping: bool = True) -> None: ...
    def step(self, dt: Optional[float] = None) -> None: ...
    def advance(self, frame_time: float, max_steps: int = 8) -> int: ...
    # Bodies.
    def create_body(self, *, type: Union[str, BodyType] = "dynamic",
                    position: Vec3Like = (0, 0, 0), orientation: QuatLike = (1, 0, 0, 0),
                    velocity: Vec3Like = (0, 0, 0), angular_velocity: Vec3Like = (0, 0, 0),
                    linear_damping: float = 0, angular_damping: float = 0,
                    gravity_scale: float = 1, mass: float = 0, inertia: Vec3Like = (0, 0, 0),
                    allow_sleep: bool = True, bullet: bool = False, name: str = "") -> BodyId: ...
    def destroy_body(self, body: BodyId) -> None: ...
    def add_shape(self, body: BodyId, shape: Shape, material: Material = ..., *,
                  position: Optional[Vec3Like] = None,
                  orientation: Optional[QuatLike] = None) -> ShapeId: ...
    def remove_shape(self, shape: ShapeId) -> None: ...
    def set_filter(self, shape: ShapeId, *, category: int = 1, mask: int = 0xFFFFFFFF,
                   group: int = 0) -> None:
        """Box2D's rule: the same non-zero group always collides (> 0) or never (< 0);
        otherwise each one's category bits must meet the other's mask."""
    def filter(self, shape: ShapeId) -> tuple[int, int, int]:
        """(category, mask, group)"""
    @overload
    def is_valid(self, id: BodyId) -> bool: ...
    @overload
    def is_valid(self, id: JointId) -> bool: ...
    @overload
    def is_valid(self, id: ParticleSystemId) -> bool: ...
    @overload
    def is_valid(self, id: DeformableId) -> bool: ...
    @overload
    def is_valid(self, id: ArticulationId) -> bool: ...
    def bodies(self) -> list[BodyId]: ...
    def shapes(self, body: BodyId) -> list[ShapeId]: ...
    def shape_body(self, shape: ShapeId) -> BodyId: ...
    def find_body(self, name: str) -> BodyId: ...
    def body_name(self, body: BodyId) -> str: ...
    def body_type(self, body: BodyId) -> BodyType: ...
    def is_awake(self, body: BodyId) -> bool: ...
    def position(self, body: BodyId) -> Array: ...
    def orientation(self, body: BodyId) -> Array: ...
    def linear_velocity(self, body: BodyId) -> Array: ...
    def angular_velocity(self, body: BodyId) -> Array: ...
    def center_of_mass(self, body: BodyId) -> Array: ...
    def mass(self, body: BodyId) -> float: ...
    def inertia(self, body: BodyId) -> Array: ...
    def set_position(self, body: BodyId, position: Vec3Like) -> None: ...
    def set_orientation(self, body: BodyId, orientation: QuatLike) -> None: ...
    def set_linear_velocity(self, body: BodyId, velocity: Vec3Like) -> None: ...
    def set_angular_velocity(self, body: BodyId, angular_velocity: Vec3Like) -> None: ...
    def move_kinematic(self, body: BodyId, position: Vec3Like, orientation: QuatLike,
                       dt: float) -> None: ...
    def apply_force(self, body: BodyId, force: Vec3Like,
                    point: Optional[Vec3Like] = None) -> None: ...
    def apply_torque(self, body: BodyId, torque: Vec3Like) -> None: ...
    def apply_impulse(self, body: BodyId, impulse: Vec3Like,
                      point: Optional[Vec3Like] = None) -> None: ...
    def apply_angular_impulse(self, body: BodyId, impulse: Vec3Like) -> None: ...
    def wake(self, body: BodyId) -> None: ...
    # Every body's state, in bodies() order.
    def positions(self) -> Array: ...
    def orientations(self) -> Array: ...
    def linear_velocities(self) -> Array: ...
    def angular_velocities(self) -> Array: ...
    def set_positions(self, positions: npt.ArrayLike) -> None: ...
    def set_orientations(self, orientations: npt.ArrayLike) -> None: ...
    def set_linear_velocities(self, velocities: npt.ArrayLike) -> None: ...
    def set_angular_velocities(self, angular_velocities: npt.ArrayLike) -> None: ...
    def kinetic_energy(self) -> float: ...
    def linear_momentum(self) -> Array: ...
    def angular_momentum(self, about: Vec3Like = (0, 0, 0)) -> Array: ...
    # Contacts, queries, snapshots.
    def contacts(self) -> list[Contact]: ...
    def contact_begin_events(self) -> list[ContactEvent]: ...
    def contact_end_events(self) -> list[ContactEvent]: ...
    def cast_ray(self, origin: Vec3Like, direction: Vec3Like,
                 max_distance: float = 1e4) -> Optional[RayHit]: ...
    def save_state(self) -> WorldState: ...
    def restore_state(self, state: WorldState) -> None: ...
    # Joints.
    def create_joint(self, settings: JointSettings) -> JointId: ...
    def destroy_joint(self, joint: JointId) -> None: ...
    def joints(self) -> list[JointId]: ...
    def joint_type(self, joint: JointId) -> str: ...
    def joint_name(self, joint: JointId) -> str: ...
    def joint_bodies(self, joint: JointId) -> tuple[Optional[BodyId], BodyId]: ...
    def set_joint_enabled(self, joint: JointId, enabled: bool) -> None: ...
    def is_joint_enabled(self, joint: JointId) -> bool: ...
    def is_joint_broken(self, joint: JointId) -> bool: ...
    def set_joint_motor(self, joint: JointId, motor: Optional[JointMotor]) -> None: ...
    def set_joint_limits(self, joint: JointId, limits: LimitsLike) -> None: ...
    def set_joint_spring(self, joint: JointId, spring: Optional[JointSpring]) -> None: ...
    def set_joint_axis(self, joint: JointId, axis: int, settings: JointAxis) -> None: ...
    def joint_force(self, joint: JointId) -> Array: ...
    def joint_torque(self, joint: JointId) -> Array: ...
    def joint_coordinate(self, joint: JointId) -> float: ...
    def joint_axis_coordinate(self, joint: JointId, axis: int) -> float: ...
    def joint_error(self, joint: JointId) -> tuple[float, float]: ...
    def joint_anchors(self, joint: JointId) -> tuple[Array, Array]: ...
    def joint_events(self) -> list[JointEvent]: ...
    # Articulations (reduced coordinates; their links are bodies named NAME/LINK).
    def create_articulation(self, model: ArticulationModel, *, name: str = "",
                            position: Optional[Vec3Like] = None,
                            orientation: Optional[QuatLike] = None,
                            q: Optional[npt.ArrayLike] = None, qd: Optional[npt.ArrayLike] = None,
                            constraint_iterations: int = 20,
                            limit_baumgarte: float = 0.2,
                            self_collision: bool = False) -> Articulation:
        """The base frame at position (m) and orientation [w, x, y, z]; q (nq,) and qd (nv,)
        the initial state (default: the neutral configuration at rest)."""
    def destroy_articulation(self, articulation: Union[Articulation, ArticulationId]) -> None: ...
    def articulations(self) -> list[Articulation]: ...
    def find_articulation(self, name: str) -> Articulation: ...
    def articulation(self, id: ArticulationId) -> Articulation: ...
    # Particle systems.
    def create_particle_system(self, *, name: str = "", capacity: int = 10000,
                               integrator: str = "symplectic_euler", restitution: float = 0.5,
                               friction: float = 0.1, restitution_threshold: float = 0.05,
                               particle_collisions: bool = False,
                               collide_with_bodies: bool = False) -> ParticleSystemId: ...
    def destroy_particle_system(self, system: ParticleSystemId) -> None: ...
    def particle_systems(self) -> list[ParticleSystemId]: ...
    def particle_system_name(self, system: ParticleSystemId) -> str: ...
    def add_emitter(self, system: ParticleSystemId, emitter: Emitter) -> int: ...
    def add_field(self, system: ParticleSystemId, field: Field,
                  region: Optional[tuple[Vec3Like, Vec3Like]] = None) -> int: ...
    def add_obstacle(self, system: ParticleSystemId, shape: Shape, *,
                     position: Optional[Vec3Like] = None,
                     orientation: Optional[QuatLike] = None) -> int: ...
    def particle_count(self, system: ParticleSystemId) -> int: ...
    def particle_stats(self, system: ParticleSystemId) -> dict[str, int]: ...
    def particle_positions(self, system: ParticleSystemId) -> Array: ...
    def particle_velocities(self, system: ParticleSystemId) -> Array: ...
    def particle_ages(self, system: ParticleSystemId) -> Array: ...
    def particle_ids(self, system: ParticleSystemId) -> Array: ...
    def set_particle_positions(self, system: ParticleSystemId,
                               positions: npt.ArrayLike) -> None: ...
    def set_particle_velocities(self, system: ParticleSystemId,
                                velocities: npt.ArrayLike) -> None: ...
    # Deformables (gravity acts only through their fields).
    def create_deformable(self, model: MassSpringModel, *, name: str = "",
                          integrator: str = "implicit_euler", thickness: float = 0.01,
                          friction: float = 0.3, tear_strain: float = 0,
                          solver_tolerance: float = 1e-6, solver_max_iterations: int = 1000,
                          linear_solver: str = "automatic",
                          collide_with_bodies: bool = True) -> DeformableId: ...
    def destroy_deformable(self, deformable: DeformableId) -> None: ...
    def deformables(self) -> list[DeformableId]: ...
    def deformable_name(self, deformable: DeformableId) -> str: ...
    def add_deformable_field(self, deformable: DeformableId, field: Field,
                             region: Optional[tuple[Vec3Like, Vec3Like]] = None) -> int: ...
    def add_deformable_obstacle(self, deformable: DeformableId, shape: Shape, *,
                                position: Optional[Vec3Like] = None,
                                orientation: Optional[QuatLike] = None) -> int: ...
    def deformable_vertex_count(self, deformable: DeformableId) -> int: ...
    def deformable_positions(self, deformable: DeformableId) -> Array:
        """(n, 3) metres: a read-only view of the deformable's memory."""
    def deformable_velocities(self, deformable: DeformableId) -> Array:
        """(n, 3) m/s: a read-only view."""
    def deformable_masses(self, deformable: DeformableId) -> Array:
        """(n,) kg: a read-only view."""
    def set_deformable_positions(self, deformable: DeformableId,
                                 positions: npt.ArrayLike) -> None: ...
    def set_deformable_velocities(self, deformable: DeformableId,
                                  velocities: npt.ArrayLike) -> None: ...
    def set_vertex_pinned(self, deformable: DeformableId, vertex: int,
                          pinned: bool = True) -> None: ...
    def is_vertex_pinned(self, deformable: DeformableId, vertex: int) -> bool: ...
    def deformable_springs(self, deformable: DeformableId) -> Array: ...
    def deformable_broken(self, deformable: DeformableId) -> Array: ...
    def deformable_triangles(self, deformable: DeformableId) -> Array: ...
    def deformable_energy(self, deformable: DeformableId) -> dict[str, float]: ...
    # Pickling: a world made from a scene pickles as the scene and the steps it took
    # (TypeError for one built or changed through the API).
    def __getstate__(self) -> tuple[Any, ...]: ...
    def __setstate__(self, state: tuple[Any, ...]) -> None: ...

# Articulations: models, the algorithms over (model, q, qd), and a World's articulations.
# q (nq,): angles (rad), displacements (m), unit quaternions [w, x, y, z] (spherical joints; a
# floating base's position then quaternion); qd (nv,): rates (rad/s, m/s).

LinkLike = Union[int, str]

class Drive:
    """PD drive: clamp(stiffness (target - q) + damping (target_velocity - qd), +-max_force)."""
    stiffness: float
    """N m/rad or N/m"""
    damping: float
    """N m s/rad or N s/m"""
    target: float
    """rad or m"""
    target_velocity: float
    """rad/s or m/s"""
    max_force: float
    """N m or N"""
    def __init__(self, *, stiffness: float = 0, damping: float = 0, target: float = 0,
                 target_velocity: float = 0, max_force: float = ...) -> None: ...

class LinkShape:
    """A collision shape of a link, at a pose in the link's frame."""
    shape: Shape
    material: Material
    position: Array
    orientation: Array
    def __init__(self, shape: Shape, material: Material = ..., *,
                 position: Optional[Vec3Like] = None,
                 orientation: Optional[QuatLike] = None) -> None: ...

class ArticulationModel:
    """A tree of links, each on one joint to its parent (or the base); parents first."""
    link_count: int
    nq: int
    nv: int
    gravity: Array
    """In the base frame (m/s^2), for the functions of (model, q, ...)."""
    shape_count: int
    lower: Array
    upper: Array
    damping: Array
    friction: Array
    armature: Array
    velocity_limit: Array
    drives: list[Drive]
    def __init__(self) -> None: ...
    def add_link(self, name: str = "", *, parent: Optional[LinkLike] = None,
                 joint: str = "revolute", axis: Vec3Like = (0, 0, 1),
                 origin_position: Vec3Like = (0, 0, 0),
                 origin_orientation: QuatLike = (1, 0, 0, 0),
                 limits: Optional[tuple[float, float]] = None, damping: float = 0,
                 friction: float = 0, armature: float = 0, velocity_limit: float = ...,
                 drive: Optional[Drive] = None, mass: Optional[float] = None,
                 com: Optional[Vec3Like] = None, inertia: Optional[npt.ArrayLike] = None,
                 shapes: Sequence[LinkShape] = ...) -> int:
        """joint: 'revolute', 'prismatic', 'spherical', 'fixed' or 'floating' (a root only).
        mass (kg), com (m) and inertia (kg m^2, principal moments or 3x3 about the com), or
        None: from the shapes' volumes and densities. Returns the link's index."""
    def find_link(self, name: str) -> int: ...
    def link(self, link: LinkLike) -> dict[str, Any]:
        """name, parent, joint, q_slice, v_slice, mass (kg), com (m)."""
    def link_names(self) -> list[str]: ...
    def neutral_configuration(self) -> Array: ...
    def set_drive(self, dof: int, drive: Drive) -> None: ...
    @staticmethod
    def random_tree(*, links: int = 10, floating_base: bool = False, armature: bool = True,
                    seed: int = 1) -> ArticulationModel: ...
    @staticmethod
    def pendulum_chain(*, links: int, length: float, mass: float) -> ArticulationModel: ...
    @staticmethod
    def seven_dof_arm() -> ArticulationModel: ...
    def random_state(self, seed: int = 1) -> tuple[Array, Array]: ...

class Articulation:
    """A World's articulation (World.create_articulation); raises InvalidArgument once
    destroyed."""
    id: ArticulationId
    world: World
    name: str
    model: ArticulationModel
    """A copy, without shapes, in the world's gravity (base axes)."""
    nq: int
    nv: int
    link_count: int
    q: Array
    """(nq,), a read-only view of the world's memory (the steps update it)."""
    qd: Array
    """(nv,), a read-only view."""
    drives: list[Drive]
    constraint_impulses: Array
    """(nv,) N m s or N s."""
    def is_valid(self) -> bool: ...
    def set_state(self, q: npt.ArrayLike, qd: Optional[npt.ArrayLike] = None) -> None: ...
    def set_joint_forces(self, tau: npt.ArrayLike) -> None:
        """(nv,) N m or N, applied every step until changed."""
    def set_drive_target(self, dof: int, target: float, target_velocity: float = 0) -> None: ...
    def set_drive_targets(self, targets: npt.ArrayLike,
                          target_velocities: Optional[npt.ArrayLike] = None) -> None: ...
    def set_drive(self, dof: int, drive: Drive) -> None: ...
    def link_bodies(self) -> list[BodyId]: ...
    def link_positions(self) -> Array:
        """(n, 3) m, world."""
    def link_orientations(self) -> Array:
        """(n, 4) [w, x, y, z], world."""
    def link_linear_velocities(self) -> Array: ...
    def link_angular_velocities(self) -> Array: ...

def aba(model: ArticulationModel, q: npt.ArrayLike, qd: npt.ArrayLike,
        tau: npt.ArrayLike) -> Array:
    """Forward dynamics (Featherstone's ABA): qdd (nv,) under gravity and tau (N m or N)."""
def forward_dynamics_crba(model: ArticulationModel, q: npt.ArrayLike, qd: npt.ArrayLike,
                          tau: npt.ArrayLike) -> Array: ...
def rnea(model: ArticulationModel, q: npt.ArrayLike, qd: npt.ArrayLike,
         qdd: npt.ArrayLike) -> Array:
    """Inverse dynamics (recursive Newton-Euler): tau (nv,) giving qdd under gravity."""
def crba(model: ArticulationModel, q: npt.ArrayLike) -> Array:
    """The mass matrix H(q), (nv, nv)."""
def point_jacobian(model: ArticulationModel, q: npt.ArrayLike, link: LinkLike,
                   point: Vec3Like = (0, 0, 0)) -> Array:
    """(6, nv): [w; v] = J qd in base axes."""
def link_pose(model: ArticulationModel, q: npt.ArrayLike,
              link: LinkLike) -> tuple[Array, Array]: ...
def point_position(model: ArticulationModel, q: npt.ArrayLike, link: LinkLike,
                   point: Vec3Like = (0, 0, 0)) -> Array: ...
def integrate_configuration(model: ArticulationModel, q: npt.ArrayLike, qd: npt.ArrayLike,
                            h: float) -> Array: ...
def kinetic_energy(model: ArticulationModel, q: npt.ArrayLike, qd: npt.ArrayLike) -> float:
    """J"""
def potential_energy(model: ArticulationModel, q: npt.ArrayLike) -> float:
    """J, in the model's gravity, zero at the base origin."""
def center_of_mass(model: ArticulationModel, q: npt.ArrayLike) -> Array:
    """m, base frame."""
def momentum(model: ArticulationModel, q: npt.ArrayLike, qd: npt.ArrayLike) -> Array:
    """[angular (kg m^2/s); linear (kg m/s)] about the base origin."""

# Deformable models (DESIGN.md; the library's generators). Masses in kg (totals), stiffness
# per spring in N/m, damping per spring in N s/m.

class MassSpringModel:
    vertex_count: int
    positions: Array
    masses: Array
    spring_count: int
    triangle_count: int
    pinned: list[int]

def rope(*, start: Vec3Like = (0, 0, 0), end: Vec3Like = (1, 0, 0), segments: int = 10,
         mass: float = 1, stretch: float = 5000, bend: float = 5, damping: float = 0,
         pinned: Sequence[int] = ()) -> MassSpringModel: ...
def cloth(*, position: Optional[Vec3Like] = None, orientation: Optional[QuatLike] = None,
          size: tuple[float, float] = (1, 1), resolution: tuple[int, int] = (10, 10),
          mass: float = 1, stretch: float = 5000, shear: float = 500, bend: float = 5,
          damping: float = 0, pinned: Sequence[int] = ()) -> MassSpringModel: ...
def soft_box(*, position: Optional[Vec3Like] = None, orientation: Optional[QuatLike] = None,
             half_extents: Vec3Like = (0.5, 0.5, 0.5), resolution: Sequence[int] = (4, 4, 4),
             mass: float = 1, stretch: float = 5000, shear: float = 500, bend: float = 5,
             damping: float = 0, pinned: Sequence[int] = ()) -> MassSpringModel: ...
def soft_sphere(*, position: Optional[Vec3Like] = None, orientation: Optional[QuatLike] = None,
                radius: float = 0.5, subdivisions: int = 2, mass: float = 1,
                stretch: float = 5000, bend: float = 5, damping: float = 0,
                pinned: Sequence[int] = ()) -> MassSpringModel: ...

def hair(*, position: Optional[Vec3Like] = None, orientation: Optional[QuatLike] = None,
         radius: float = 0.1, cap_angle: float = 1.2, strands: int = 100, segments: int = 16,
         length: float = 0.2, mass: float = 0.05, stretch: float = 5000, bend: float = 5,
         damping: float = 0) -> MassSpringModel: ...
def soft_mesh(mesh: TriangleMesh, *, position: Optional[Vec3Like] = None,
              orientation: Optional[QuatLike] = None, resolution: int = 6, ties: int = 4,
              mass: float = 1, stretch: float = 5000, shear: float = 500, bend: float = 5,
              damping: float = 0, pinned: Sequence[int] = ()) -> MassSpringModel: ...

def load_scene(path: str, *, dt: Optional[float] = None,
               threads: Optional[int] = None) -> World: ...
def parse_scene(scene: Union[str, dict[str, Any]], name: str = "<scene>", *,
                dt: Optional[float] = None, threads: Optional[int] = None) -> World: ...

class Batch:
    """N independent worlds stepped together across the cores with one call; each gives the
    bits it gives when stepped alone. State as (N, bodies, ...) arrays."""
    body_count: int
    def __init__(self, scene: Union[str, dict[str, Any], Sequence[Union[str, dict[str, Any]]]],
                 n: Optional[int] = None, *, gravity: Optional[npt.ArrayLike] = None,
                 threads: int = 0) -> None: ...
    def __len__(self) -> int: ...
    def __getitem__(self, i: int) -> World: ...
    def step(self, steps: int = 1) -> None: ...
    def positions(self) -> Array: ...
    def orientations(self) -> Array: ...
    def linear_velocities(self) -> Array: ...
    def angular_velocities(self) -> Array: ...
    def set_positions(self, positions: npt.ArrayLike) -> None: ...
    def set_orientations(self, orientations: npt.ArrayLike) -> None: ...
    def set_linear_velocities(self, velocities: npt.ArrayLike) -> None: ...
    def set_angular_velocities(self, angular_velocities: npt.ArrayLike) -> None: ...
