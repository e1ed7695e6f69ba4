"""A rubber ball dropped on the ground: the height of each bounce against Newton's law of
restitution, h_k = e^(2k) h_0.

    PYTHONPATH=build/default/python /usr/bin/python3 python/examples/bouncing_ball.py
"""

import inertia


def bounce_heights(drop=2.0, restitution=0.8, radius=0.1, bounces=3):
    """Drops a ball from `drop` m (its bottom) and returns the heights (m) of its bottom at the
    top of each of the first `bounces` bounces."""
    world = inertia.World(gravity=(0, -9.81, 0), dt=1 / 240, substeps=4)
    ground = world.create_body(type="static")
    world.add_shape(ground, inertia.Plane((0, 1, 0), 0))
    ball = world.create_body(position=(0, drop + radius, 0), name="ball")
    world.add_shape(ball, inertia.Sphere(radius),
                    inertia.Material(density=1100, restitution=restitution))
    heights, rising = [], False
    while len(heights) < bounces and world.time < 30:
        world.step()
        vy = world.linear_velocity(ball)[1]
        if vy > 0:
            rising = True
        elif rising:  # the top of a bounce
            heights.append(float(world.position(ball)[1]) - radius)
            rising = False
    return heights


if __name__ == "__main__":
    e, h0 = 0.8, 2.0
    for k, h in enumerate(bounce_heights(h0, e), start=1):
        print(f"bounce {k}: {h:.4f} m (restitution predicts {h0 * e ** (2 * k):.4f} m)")
