# RoboClean (seed 003): go-to-goal and obstacle avoidance on odometry and a sonar on a
# servo. The firmware lives in lib/; the mission in /mission.json.
import robot

robot.run()
