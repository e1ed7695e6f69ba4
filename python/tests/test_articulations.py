"""Articulations from Python: the library's Featherstone algorithms against each other and
against closed forms, a World's articulation against a pendulum's period and a drive's static
equilibrium, the state arrays, scenes' articulations by name, and bad input."""

import gc
import math
import pickle

import numpy as np
import pytest

import inertia

EPS = float(np.finfo(inertia.real_dtype).eps)  # 1.2e-7 (float), 2.2e-16 (double)
JOINTS = ["revolute", "prismatic", "spherical", "fixed"]


def random_rotation(rng):
    q = rng.normal(size=4)
    return q / np.linalg.norm(q)


def rotation_matrix(q):
    w, x, y, z = q
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def box_inertia(rng, mass):
    """The inertia tensor of a random box turned by a random rotation: a physical one."""
    a, b, c = rng.uniform(0.1, 0.5, size=3)
    principal = mass / 12 * np.array([b * b + c * c, a * a + c * c, a * a + b * b])
    r = rotation_matrix(random_rotation(rng))
    return r @ np.diag(principal) @ r.T


def random_tree(seed, floating=False):
    """A root (revolute, or floating) and a tree below it with every joint type: prismatic and
    spherical children of the root, a fixed link on the spherical one, a revolute one below."""
    rng = np.random.default_rng(seed)
    model = inertia.ArticulationModel()
    layout = [("root", None, "floating" if floating else "revolute"),
              ("slide", "root", "prismatic"), ("ball", "root", "spherical"),
              ("weld", "ball", "fixed"), ("tip", "weld", "revolute")]
    for name, parent, joint in layout:
        mass = rng.uniform(0.5, 2)
        scalar = joint in ("revolute", "prismatic")
        model.add_link(name, parent=parent, joint=joint, axis=rng.normal(size=3),
                       origin_position=rng.uniform(-0.5, 0.5, size=3),
                       origin_orientation=random_rotation(rng),
                       armature=rng.uniform(0, 0.1) if scalar else 0, mass=mass,
                       com=rng.uniform(-0.2, 0.2, size=3), inertia=box_inertia(rng, mass))
    q = model.neutral_configuration().astype(np.float64)
    for i in range(model.link_count):
        link = model.link(i)
        sl = link["q_slice"]
        if link["joint"] in ("revolute", "prismatic"):
            q[sl] = rng.uniform(-1, 1)
        elif link["joint"] == "spherical":
            q[sl] = random_rotation(rng)
        elif link["joint"] == "floating":
            q[sl] = np.concatenate([rng.uniform(-1, 1, 3), random_rotation(rng)])
    qd = rng.uniform(-1, 1, model.nv)
    tau = rng.uniform(-2, 2, model.nv)
    return model, q, qd, tau


@pytest.mark.parametrize("floating", [False, True])
@pytest.mark.parametrize("seed", [1, 2, 3])
def test_aba_solves_crba_with_rnea_bias(seed, floating):
    model, q, qd, tau = random_tree(seed, floating)
    assert {model.link(i)["joint"] for i in range(model.link_count)} >= set(JOINTS[1:])
    qdd = inertia.aba(model, q, qd, tau).astype(np.float64)
    H = inertia.crba(model, q).astype(np.float64)
    bias = inertia.rnea(model, q, qd, np.zeros(model.nv)).astype(np.float64)
    assert H.shape == (model.nv, model.nv) and qdd.shape == (model.nv,)
    np.testing.assert_array_equal(H, H.T)  # CRBA fills the symmetric half from the other
    assert np.all(np.linalg.eigvalsh(H) > 0)
    oracle = np.linalg.solve(H, tau - bias)
    # Both sides are backward-stable sums of a few hundred rounded products per link, so their
    # forward errors are about cond(H) eps |qdd| (cond(H) 26 to 307 over these trees; measured
    # at most 0.08 cond(H) eps |qdd|). A wrong term of the dynamics is an error of order |qdd|.
    bound = np.linalg.cond(H) * EPS * np.linalg.norm(oracle)
    assert np.linalg.norm(qdd - oracle) <= bound
    # The library's other forward dynamics (CRBA and Cholesky in Real) agrees the same way.
    crba_fd = inertia.forward_dynamics_crba(model, q, qd, tau).astype(np.float64)
    assert np.linalg.norm(crba_fd - oracle) <= bound


@pytest.mark.parametrize("floating", [False, True])
def test_the_librarys_random_trees_and_arm_agree_the_same_way(floating):
    # The library's own builders: ten links cycling through the joint types, and a Panda arm.
    for model in (inertia.ArticulationModel.random_tree(links=10, floating_base=floating, seed=7),
                  inertia.ArticulationModel.seven_dof_arm()):
        q, qd = model.random_state(seed=3)
        assert q.shape == (model.nq,) and qd.shape == (model.nv,)
        tau = np.linspace(-1, 1, model.nv)
        H = inertia.crba(model, q).astype(np.float64)
        bias = inertia.rnea(model, q, qd, np.zeros(model.nv)).astype(np.float64)
        oracle = np.linalg.solve(H, tau - bias)
        qdd = inertia.aba(model, q, qd, tau).astype(np.float64)
        # As above: cond(H) eps |qdd|.
        assert np.linalg.norm(qdd - oracle) <= np.linalg.cond(H) * EPS * np.linalg.norm(oracle)
    chain = inertia.ArticulationModel.pendulum_chain(links=3, length=0.5, mass=2)
    # Hanging straight down, its centre of mass is at the middle link's end: -(0.5+1+1.5)/3 m.
    np.testing.assert_allclose(inertia.center_of_mass(chain, np.zeros(3)), [0, -1, 0], atol=1e-6)
    with pytest.raises(ValueError, match="links"):
        inertia.ArticulationModel.random_tree(links=0)


@pytest.mark.parametrize("seed", [4, 5])
def test_rnea_inverts_aba(seed):
    model, q, qd, tau = random_tree(seed, floating=seed == 5)
    qdd = inertia.aba(model, q, qd, tau)
    back = inertia.rnea(model, q, qd, qdd).astype(np.float64)
    H = inertia.crba(model, q).astype(np.float64)
    # tau = H qdd + C: qdd rounded by cond(H) eps |qdd| (above) moves tau by |H| times that
    # (measured at most 0.015 of it).
    bound = np.linalg.cond(H) * EPS * np.linalg.norm(H, 2) * np.linalg.norm(qdd)
    assert np.linalg.norm(back - tau) <= bound


def test_energy_momentum_and_jacobian_agree_with_the_mass_matrix():
    model, q, qd, _ = random_tree(6)
    H = inertia.crba(model, q).astype(np.float64)
    kinetic = inertia.kinetic_energy(model, q, qd)
    # 1/2 qd . H qd: two routes, a few hundred roundings each.
    assert kinetic == pytest.approx(0.5 * qd @ H @ qd, rel=1e3 * EPS)
    # The tip's point velocity by its Jacobian equals the finite difference of its position.
    point = np.array([0.1, -0.2, 0.3])
    J = inertia.point_jacobian(model, q, "tip", point).astype(np.float64)
    assert J.shape == (6, model.nv)
    h = 1e-2 if EPS > 1e-10 else 1e-5
    x0 = inertia.point_position(model, q, "tip", point).astype(np.float64)
    x1 = inertia.point_position(model, inertia.integrate_configuration(model, q, qd, h),
                                "tip", point).astype(np.float64)
    # Forward difference: O(h |x''|) truncation (|x''| < 10 m/s^2 here) and eps/h rounding.
    np.testing.assert_allclose((x1 - x0) / h, J[3:] @ qd, atol=10 * h + 10 * EPS / h)
    position, orientation = inertia.link_pose(model, q, "tip")
    assert position.shape == (3,) and orientation.shape == (4,)
    assert np.linalg.norm(orientation) == pytest.approx(1, abs=10 * EPS)
    com = inertia.center_of_mass(model, q)
    masses = [model.link(i)["mass"] for i in range(model.link_count)]
    assert com.shape == (3,) and sum(masses) > 0
    assert inertia.momentum(model, q, qd).shape == (6,)


def pendulum(d=0.5, mass=2.0, inertia_cm=0.01):
    """One link on a revolute joint about z, its centre of mass d below the joint."""
    model = inertia.ArticulationModel()
    model.add_link("bob", joint="revolute", axis=(0, 0, 1), mass=mass, com=(0, -d, 0),
                   inertia=(inertia_cm, inertia_cm, inertia_cm))
    return model


def crossings(times, values):
    """Times where values cross zero upwards, by linear interpolation."""
    out = []
    for k in range(1, len(values)):
        if values[k - 1] < 0 <= values[k]:
            f = values[k - 1] / (values[k - 1] - values[k])
            out.append(times[k - 1] + f * (times[k] - times[k - 1]))
    return out


def test_pendulum_small_angle_period():
    g, d, m, ic, theta0 = 9.81, 0.5, 2.0, 0.01, 0.02
    world = inertia.World(gravity=(0, -g, 0), dt=1 / 240, substeps=4)
    art = world.create_articulation(pendulum(d, m, ic), name="pendulum", q=[theta0])
    times, angles = [], []
    for _ in range(240 * 6):
        world.step()
        times.append(world.time)
        angles.append(float(art.q[0]))
    up = crossings(times, angles)
    period = (up[-1] - up[0]) / (len(up) - 1)
    inertia_pivot = ic + m * d * d
    small = 2 * math.pi * math.sqrt(inertia_pivot / (m * g * d))
    # The two known corrections: the finite amplitude lengthens the period by theta0^2 / 16
    # (2.5e-5; the next term, 11 theta0^4 / 3072, is 6e-10), and the substeps' semi-implicit
    # Euler shortens it by (omega h)^2 / 24 (8.7e-7 at omega = 4.4 rad/s, h = 1/960 s). The
    # crossings are interpolated where the angle is nearly straight (third order in h). What is
    # left is float rounding of the angle over 5,760 substeps: measured 1e-8; 1e-6 allows for
    # it and still tells the amplitude term (25 times larger) and a point-mass period (I = m
    # d^2, 1% off).
    omega, h = 2 * math.pi / small, 1 / 960
    expected = small * (1 + theta0**2 / 16) * (1 - (omega * h) ** 2 / 24)
    assert period == pytest.approx(expected, rel=1e-6)
    assert abs(period - small) > 20 * 1e-6 * small

def driven_arm(stiffness, damping, target):
    """A horizontal link along x on a revolute joint about z (gravity pulls it down) whose PD
    drive holds it at target."""
    model = inertia.ArticulationModel()
    model.add_link("arm", joint="revolute", axis=(0, 0, 1), mass=2.0, com=(0.3, 0, 0),
                   inertia=(0.006, 0.06, 0.06),
                   drive=inertia.Drive(stiffness=stiffness, damping=damping, target=target))
    return model


def test_drive_holds_the_static_equilibrium():
    g, m, d, k, target = 9.81, 2.0, 0.3, 400.0, 0.4
    inertia_pivot = 0.06 + m * d * d
    c = 2 * math.sqrt(k * inertia_pivot)  # critically damped
    world = inertia.World(gravity=(0, -g, 0), dt=1 / 240, substeps=4)
    art = world.create_articulation(driven_arm(k, c, target), q=[target])
    for _ in range(240 * 2):
        world.step()
    # Static balance of drive and gravity: k (target - q) = m g d cos q, by fixed point.
    q = target
    for _ in range(50):
        q = target - m * g * d * math.cos(q) / k
    # The drive is implicit in q(t+h), so its rest point is the exact balance; the transient
    # after 2 s, (1 + omega t) e^(-omega t) with omega = 41 rad/s, is gone. Left is float
    # rounding of the balance (measured 1.1e-7 rad, 2e-6 rad/s); a drive without gravity's
    # share would rest 0.014 rad away.
    assert float(art.q[0]) == pytest.approx(q, abs=1e-6)
    assert abs(float(art.qd[0])) < 2e-5
    # At rest, the drive's impulse in each substep carries gravity's torque over it:
    # m g d cos(q) h with h = 1/960 s, to float rounding (measured 2e-7 relative; 1e-5 allows
    # for it, and an impulse per step instead of per substep would be 4 times larger).
    torque = m * g * d * math.cos(float(art.q[0]))
    assert float(art.constraint_impulses[0]) == pytest.approx(torque / 960, rel=1e-5)
    # A new target moves it to the new balance.
    art.set_drive_target(0, -0.2)
    for _ in range(240 * 2):
        world.step()
    q = -0.2
    for _ in range(50):
        q = -0.2 - m * g * d * math.cos(q) / k
    assert float(art.q[0]) == pytest.approx(q, abs=1e-6)
    assert art.drives[0].target == pytest.approx(-0.2)
    # set_drive_targets moves every drive in one call (the model's drives are copies).
    art.set_drive_targets([0.1])
    assert art.drives[0].target == pytest.approx(0.1)
    assert art.model.drives[0].target == pytest.approx(0.1)
    for _ in range(240 * 2):
        world.step()
    q = 0.1
    for _ in range(50):
        q = 0.1 - m * g * d * math.cos(q) / k
    assert float(art.q[0]) == pytest.approx(q, abs=1e-6)


def bar():
    """A 0.6 x 0.1 x 0.1 m box along a link's x from its joint, 500 kg/m^3."""
    return inertia.LinkShape(inertia.Box((0.3, 0.05, 0.05)), inertia.Material(density=500),
                             position=(0.3, 0, 0))


def two_link_model():
    model = inertia.ArticulationModel()
    shape = bar()
    model.add_link("upper", joint="revolute", axis=(0, 0, 1), shapes=[shape])
    model.add_link("fore", parent="upper", joint="spherical", origin_position=(0.6, 0, 0),
                   shapes=[shape])
    return model


def test_q_and_qd_view_the_worlds_memory():
    # Read-only views, as the particles' (the library trusts what it stores): they see the
    # steps and set_state without a copy, and hold the articulation against destruction.
    world = inertia.World()
    art = world.create_articulation(two_link_model(), name="arm")
    q, qd = art.q, art.qd
    assert np.shares_memory(q, art.q) and np.shares_memory(qd, art.qd)
    with pytest.raises(ValueError, match="read-only"):
        q[0] = 1
    art.set_state(q, qd + 0.5)  # q is read before it is written
    before = q.copy()
    world.step()
    np.testing.assert_array_equal(q, art.q)
    assert not np.array_equal(q, before)  # gravity swung the arm: the view followed
    with pytest.raises(ValueError, match="2 NumPy arrays still view its state"):
        world.destroy_articulation(art)
    del q, qd
    world.destroy_articulation(art)
    assert not art.is_valid()


def test_arrays_have_their_shapes_and_writing_them_moves_the_links():
    model = two_link_model()
    assert (model.nq, model.nv, model.link_count, model.shape_count) == (5, 4, 2, 2)
    # Mass from the shapes: 0.6 x 0.1 x 0.1 m of 500 kg/m^3.
    assert model.link("upper")["mass"] == pytest.approx(3.0, rel=1e-6)
    world = inertia.World(gravity=(0, 0, 0))
    base = np.array([1.0, 2.0, 3.0])
    art = world.create_articulation(model, name="arm", position=base)
    assert art.q.shape == (5,) and art.qd.shape == (4,)
    assert art.link_positions().shape == (2, 3) and art.link_orientations().shape == (2, 4)
    assert art.link_linear_velocities().shape == (2, 3)
    assert art.link_angular_velocities().shape == (2, 3)
    assert art.q.dtype == inertia.real_dtype
    np.testing.assert_allclose(art.link_positions()[1], base + (0.6, 0, 0), atol=1e-6)
    # Turn the shoulder a quarter turn and spin the elbow: the links follow at once, where the
    # library's kinematics (another route: the model's link poses) puts them.
    quarter = math.sqrt(0.5)
    q = np.array([math.pi / 2, quarter, 0, 0, quarter])
    art.set_state(q, [0.5, 0, 0, 1])
    np.testing.assert_allclose(art.q, q, atol=1e-6)
    np.testing.assert_allclose(art.qd, [0.5, 0, 0, 1], atol=0)
    for i in range(2):
        position, orientation = inertia.link_pose(art.model, art.q, i)
        np.testing.assert_allclose(art.link_positions()[i], base + position, atol=1e-6)
        assert abs(np.dot(art.link_orientations()[i], orientation)) == pytest.approx(1, abs=1e-6)
    np.testing.assert_allclose(art.link_positions()[1], base + (0, 0.6, 0), atol=1e-6)
    # The link bodies move with the joint rates: the shoulder turns the upper link at 0.5 rad/s
    # about z, so its centre of mass, 0.3 m out along the link (now along y), moves at
    # w x r = (-0.15, 0, 0) m/s.
    np.testing.assert_allclose(art.link_angular_velocities()[0], [0, 0, 0.5], atol=1e-6)
    np.testing.assert_allclose(art.link_linear_velocities()[0], [-0.15, 0, 0], atol=1e-6)
    # The body list sees the same poses.
    bodies = art.link_bodies()
    np.testing.assert_allclose(world.position(bodies[1]), art.link_positions()[1])
    assert world.body_name(bodies[0]) == "arm/upper"
    # Joint forces act: a torque on the shoulder spins it up at tau / H_00.
    art.set_state(model.neutral_configuration(), np.zeros(4))
    H = inertia.crba(art.model, art.q)
    art.set_joint_forces([1.0, 0, 0, 0])
    world.step()
    accel = float(art.qd[0]) / world.dt
    assert accel == pytest.approx(float(np.linalg.solve(H, [1.0, 0, 0, 0])[0]), rel=1e-3)


def test_self_collision_makes_contacts_between_a_trees_own_links():
    # Three 0.6 m bars on z hinges folded into a Z: the third crosses the first (two links
    # apart), each bar touches its neighbours at their hinges. Only with self_collision is
    # there a contact, and only between the first and the third.
    model = inertia.ArticulationModel()
    shape = bar()
    model.add_link("a", joint="revolute", axis=(0, 0, 1), shapes=[shape])
    model.add_link("b", parent="a", joint="revolute", axis=(0, 0, 1),
                   origin_position=(0.6, 0, 0), shapes=[shape])
    model.add_link("c", parent="b", joint="revolute", axis=(0, 0, 1),
                   origin_position=(0.6, 0, 0), shapes=[shape])
    pairs = {}
    for self_collision in (False, True):
        world = inertia.World(gravity=(0, 0, 0))
        art = world.create_articulation(model, name="z", q=[0, 2.9, 2.9],
                                        self_collision=self_collision)
        world.step()
        names = [sorted((world.body_name(c.body_a), world.body_name(c.body_b)))
                 for c in world.contacts()]
        pairs[self_collision] = names
        assert np.all(np.isfinite(art.q))
    assert pairs[False] == []
    assert pairs[True] == [["z/a", "z/c"]]


def test_scene_articulations_by_name(scenes):
    world = inertia.load_scene(str(scenes / "articulations.json"))
    names = [a.name for a in world.articulations()]
    assert names == ["arm", "walker"]
    arm = world.find_articulation("arm")
    assert arm == world.articulations()[0] and arm.nq == 2 and arm.nv == 2
    walker = world.find_articulation("walker")
    assert walker.nq == 8 and walker.nv == 7  # floating base (7 + 6) and a revolute leg
    assert walker.model.link("body")["joint"] == "floating"
    np.testing.assert_allclose(walker.q[:3], [-1.5, 1.5, 0])
    assert arm.drives[0].target_velocity == pytest.approx(-1)
    with pytest.raises(KeyError, match="nobody"):
        world.find_articulation("nobody")
    # A scene world still pickles until it is changed from Python.
    world.step()
    copy = pickle.loads(pickle.dumps(world))
    np.testing.assert_array_equal(copy.find_articulation("walker").q, walker.q)
    arm.set_drive_target(1, 0.5)
    with pytest.raises(TypeError, match="changed"):
        pickle.dumps(world)


def test_save_state_holds_articulations(scenes):
    # The walker lands and the arm sweeps under its drives: a restored world continues with
    # the same joint coordinates, bit for bit.
    world = inertia.load_scene(str(scenes / "articulations.json"))
    for _ in range(20):
        world.step()
    saved = world.save_state()

    def run():
        out = []
        for _ in range(30):
            world.step()
            out += [a.q.tobytes() + a.qd.tobytes() for a in world.articulations()]
        return out

    first = run()
    world.restore_state(saved)
    assert run() == first
    assert first[0] != first[-2]  # the arm moved


def test_stale_handles_raise_and_keep_their_world():
    world = inertia.World()
    art = world.create_articulation(pendulum())
    assert art.is_valid() and world.is_valid(art.id)
    world.destroy_articulation(art)
    assert not art.is_valid() and "destroyed" in repr(art)
    for use in (lambda: art.q, lambda: art.set_state([0]), lambda: art.link_positions(),
                lambda: art.model, lambda: art.set_drive_target(0, 1)):
        with pytest.raises(inertia.InvalidArgument, match="destroyed"):
            use()
    with pytest.raises(ValueError):
        world.destroy_articulation(art)
    # A handle keeps its world alive.
    other = inertia.World().create_articulation(pendulum(), name="kept")
    gc.collect()
    assert other.name == "kept" and other.world.body_count == 1
    with pytest.raises(ValueError, match="articulation"):
        world.destroy_articulation("arm")


def test_bad_input_names_the_argument():
    model = pendulum()
    cases = [
        (lambda: inertia.aba(model, [0, 0], [0], [0]), "q: expected 1 numbers"),
        (lambda: inertia.aba(model, [0], [float("nan")], [0]), "qd: must be finite"),
        (lambda: inertia.rnea(model, [0], [0], "x"), "qdd"),
        (lambda: inertia.point_jacobian(model, [0], 3), "link: no link 3"),
        (lambda: inertia.point_jacobian(model, [0], "elbow"), "link: no link named 'elbow'"),
        (lambda: inertia.crba(inertia.ArticulationModel(), []), "model: has no links"),
        (lambda: model.add_link("x", joint="hinge", mass=1, inertia=(1, 1, 1)), "joint"),
        (lambda: model.add_link("x", parent="nobody", mass=1, inertia=(1, 1, 1)), "parent"),
        (lambda: model.add_link("x", mass=1), "inertia: required"),
        (lambda: model.add_link("x"), "mass"),
        (lambda: model.add_link("x", mass=1, inertia=(1, 1)), "inertia"),
        (lambda: model.add_link("x", mass="heavy", inertia=(1, 1, 1)), "mass: expected a number"),
        (lambda: model.add_link("x", drive=3, mass=1, inertia=(1, 1, 1)), "drive"),
        (lambda: model.add_link("x", shapes=[inertia.Sphere(1)]), "shapes"),
        (lambda: model.add_link("x", shapes=3), "shapes"),
        (lambda: model.add_link("bob", mass=1, inertia=(1, 1, 1)), "name"),
        (lambda: model.add_link("x", axis=(0, 0, 0), mass=1, inertia=(1, 1, 1)), "axis"),
        (lambda: model.add_link("x", limits=(1, -1), mass=1, inertia=(1, 1, 1)), "limits"),
        (lambda: model.add_link("x", mass=-1, inertia=(1, 1, 1)), "mass"),
        (lambda: model.add_link("x", mass=1, inertia=(1, 1, 5)), "inertia"),
        (lambda: model.add_link("x", joint="spherical", limits=(0, 1), mass=1,
                                inertia=(1, 1, 1)), "limits"),
        (lambda: inertia.LinkShape("box"), "shape"),
    ]
    for call, message in cases:
        with pytest.raises(ValueError, match=message):
            call()
    assert model.link_count == 1  # nothing half-added
    world = inertia.World()
    art = world.create_articulation(model)
    for call, message in [
        (lambda: art.set_state([0, 1]), "q: expected 1 numbers"),
        (lambda: art.set_state([0], [1, 2]), "qd"),
        (lambda: art.set_state([float("inf")]), "q: must be finite"),
        (lambda: art.set_joint_forces([float("nan")]), "tau"),
        (lambda: art.set_drive_target(2, 0), "dof"),
        (lambda: art.set_drive_target(0, float("nan")), "target"),
        (lambda: art.set_drive_targets([0, 0]), "targets"),
        (lambda: world.create_articulation(model, q=[1, 2]), "q"),
        (lambda: world.create_articulation(model, orientation=(0, 0, 0, 0)), "orientation"),
        (lambda: world.create_articulation(model, position=(0, 1)), "position"),
        (lambda: world.create_articulation(model, constraint_iterations=0), "constraint"),
        (lambda: world.create_articulation(inertia.ArticulationModel()), "model"),
    ]:
        with pytest.raises(ValueError, match=message):
            call()
    ball = inertia.ArticulationModel()
    ball.add_link("b", joint="spherical", mass=1, inertia=(1, 1, 1))
    with pytest.raises(ValueError, match="quaternion"):
        inertia.crba(ball, [0, 0, 0, 0])
    assert world.articulations() == [art]  # the refused ones left nothing behind
    np.testing.assert_array_equal(art.q, [0])
