# The two behaviours of seed 003 and the hard switch between them (§4.3, §4.4, §5.1):
# go-to-goal steers at the goal's bearing, obstacle avoidance at the heading of the
# sweep's u_ao, both through the same heading controller. Every 500 ms the switch looks
# at the obstacle points in the body's strip towards the goal: go-to-goal gives way when
# one is within LOOK_IN_CM, avoidance hands back when the strip is clear for LOOK_OUT_CM.
# The avoidance heading is chosen when avoidance starts and held (it is a direction in
# the world) until the strip along it is blocked: chosen afresh at every step, it turns
# with the robot, since the sweep turns with it. Goals are visited in turn. Pure Python.
import math

from avoidance import LOOK_IN_CM, LOOK_OUT_CM, Obstacles
from chassis import V_CRUISE
from go_to_goal import at_goal

GO_TO_GOAL = 0
AVOID = 1
DONE = 2
MODE_NAMES = ("go-to-goal", "avoid", "done")


class Navigator:
    def __init__(self, goals, controller, v_cm_s=V_CRUISE):
        self.goals = [tuple(g) for g in goals]
        self.goal_index = 0
        self.controller = controller
        self.v = v_cm_s
        self.obstacles = Obstacles()
        self.mode = GO_TO_GOAL if self.goals else DONE
        self.reached = []  # (goal index, pose) at each arrival
        self.phi_ao = 0.0

    @property
    def goal(self):
        return self.goals[self.goal_index] if self.mode != DONE else None

    def control(self, pose):
        """Every pose update: (left PWM, right PWM)."""
        if self.mode == DONE:
            return 0, 0
        x, y, phi = pose
        xg, yg = self.goals[self.goal_index]
        if at_goal(x, y, xg, yg):
            self.reached.append((self.goal_index, pose))
            self.goal_index += 1
            self.controller.reset()
            if self.goal_index == len(self.goals):
                self.mode = DONE
            else:
                self.mode = GO_TO_GOAL
            return 0, 0
        if self.mode == AVOID:
            phi_d = self.phi_ao
        else:
            phi_d = math.atan2(yg - y, xg - x)
        return self.controller.step(phi_d, phi, self.v)

    def check(self, pose):
        """Every 500 ms: the hard switch; True if the behaviour changed."""
        if self.mode == DONE:
            return False
        goal = self.goals[self.goal_index]
        obstacles = self.obstacles
        if self.mode == GO_TO_GOAL and obstacles.blocked_to(pose, goal, LOOK_IN_CM):
            self.mode = AVOID
            self.phi_ao = obstacles.heading(pose, goal)
        elif self.mode == AVOID and not obstacles.blocked_to(pose, goal, LOOK_OUT_CM):
            self.mode = GO_TO_GOAL
        elif self.mode == AVOID and obstacles.blocked(pose, self.phi_ao, LOOK_IN_CM):
            self.phi_ao = obstacles.heading(pose, goal)
            return False
        else:
            return False
        self.controller.reset()
        return True
