# Obstacle avoidance of seed 003 (§4.4) from the servo's 5-angle sweep: each reading is a
# point in the sensor's frame, [d, 0, 1], taken to the robot's frame (T_s^r, the servo
# angle less 90 deg; the seed's homogeneous 0 made 1) and to the world's (T_r^o, the
# odometry pose). Readings taken along a sweep thus stay valid while the robot moves.
# Pure Python.
#
# u_ao is the weighted sum of the sweep's directions, alpha_i (p_i - p_robot), each reading
# capped at D_MAX_CM so that free directions pull hardest (the seed's own [x; y] - [x_o;
# y_o] points at the far walls, docs/vacuum.md). The seed leaves alpha_i open ("weigh
# each vector according to their importance"): here a direction weighs 1 + cos of its
# angle to the goal, from 0 (away from the goal) to 2 (towards it). A narrow sonar sees a
# box dead ahead with its front beam only and the sides cancel: the part of u_ao that
# points at the nearest echo is taken out, and a tie goes to the goal's side.
import math

from chassis import BODY_RADIUS_CM, SENSOR_X_CM

SWEEP_DEG = (10, 45, 90, 135, 170)  # servo angles; 90 looks ahead
D_MAX_CM = 100.0  # a reading counts at most this far: farther is free
D_SEE_CM = 150.0  # echoes nearer than this are remembered as obstacle points
MEMORY = 32  # obstacle points remembered (a point at 150 cm ahead must last until it is near)
CORRIDOR_HALF_CM = BODY_RADIUS_CM + 10.0  # the strip the body sweeps, with a margin
LOOK_IN_CM = 60.0  # an obstacle point this near in the strip to the goal: avoid
LOOK_OUT_CM = 80.0  # back to the goal when the strip is clear this far
TIE_CM = 1.0


def frame(x, y, th):
    """The homogeneous transform of a pose: [[cos, -sin, x], [sin, cos, y], [0, 0, 1]]."""
    c, s = math.cos(th), math.sin(th)
    return ((c, -s, x), (s, c, y), (0.0, 0.0, 1.0))


def apply(t, p):
    return tuple(row[0] * p[0] + row[1] * p[1] + row[2] * p[2] for row in t)


def reading_to_world(pose, servo_deg, d_cm):
    """[x_o; y_o; 1] = T_r^o T_s^r [d; 0; 1]."""
    in_robot = apply(frame(SENSOR_X_CM, 0.0, math.radians(servo_deg - 90)), (d_cm, 0.0, 1.0))
    x, y, _ = apply(frame(*pose), in_robot)
    return x, y


def in_strip(px, py, x, y, heading, length):
    """Whether (px, py) lies in the body's strip from (x, y) along heading, length long."""
    dx, dy = px - x, py - y
    c, s = math.cos(heading), math.sin(heading)
    along = dx * c + dy * s
    return 0.0 < along < length and abs(dy * c - dx * s) < CORRIDOR_HALF_CM


class Obstacles:
    """The latest reading at each sweep angle, and the last MEMORY echoes, in world cm."""

    def __init__(self):
        self.latest = [None] * len(SWEEP_DEG)
        self.points = [(0.0, 0.0)] * MEMORY
        self.count = 0

    def add(self, i, d_cm, pose):
        """The reading of sweep angle i (None: no echo) taken at pose."""
        capped = D_MAX_CM if d_cm is None or d_cm > D_MAX_CM else d_cm
        self.latest[i] = reading_to_world(pose, SWEEP_DEG[i], capped)
        if d_cm is not None and d_cm < D_SEE_CM:
            self.points[self.count % MEMORY] = reading_to_world(pose, SWEEP_DEG[i], d_cm)
            self.count += 1

    def _known(self):
        return self.points[: min(self.count, MEMORY)]

    def blocked(self, pose, heading, length):
        """Whether a remembered echo lies in the body's strip from pose along heading,
        within length."""
        x, y = pose[0], pose[1]
        for px, py in self._known():
            if in_strip(px, py, x, y, heading, length):
                return True
        return False

    def blocked_to(self, pose, goal, length):
        """blocked() along the way to the goal, no farther than the goal."""
        gx, gy = goal[0] - pose[0], goal[1] - pose[1]
        return self.blocked(pose, math.atan2(gy, gx), min(length, math.sqrt(gx * gx + gy * gy)))

    def nearest_ahead(self, pose):
        """Unit vector to the nearest remembered echo in front of the robot within
        D_MAX_CM, or None."""
        x, y, th = pose
        best, best_d = None, D_MAX_CM
        for px, py in self._known():
            dx, dy = px - x, py - y
            d = math.sqrt(dx * dx + dy * dy)
            if 0.0 < d < best_d and dx * math.cos(th) + dy * math.sin(th) > 0.0:
                best, best_d = (dx / d, dy / d), d
        return best

    def heading(self, pose, goal):
        """phi_d = atan2(u_ao) for the avoidance behaviour."""
        x, y = pose[0], pose[1]
        gx, gy = goal[0] - x, goal[1] - y
        g = math.sqrt(gx * gx + gy * gy) or 1.0
        ux = uy = 0.0
        for p in self.latest:
            if p is not None:
                dx, dy = p[0] - x, p[1] - y
                d = math.sqrt(dx * dx + dy * dy) or 1.0
                alpha = 1.0 + (dx * gx + dy * gy) / (d * g)  # 1 + cos(angle to the goal)
                ux += alpha * dx
                uy += alpha * dy
        n = self.nearest_ahead(pose)
        if n is not None:
            towards = ux * n[0] + uy * n[1]
            if towards > 0.0:  # do not drive at what was seen
                ux -= towards * n[0]
                uy -= towards * n[1]
            if math.sqrt(ux * ux + uy * uy) < TIE_CM:  # head-on, both sides alike
                side = 1.0 if n[0] * (goal[1] - y) - n[1] * (goal[0] - x) >= 0.0 else -1.0
                ux, uy = -side * n[1], side * n[0]
        return math.atan2(uy, ux)
