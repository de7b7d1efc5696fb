"""proprio.robot: the robot interface (thesis 3.x, robot::Robot): look() gives the image (RGB),
the arm's joint angles and end effector, the calibration and the arm's self-mask; push() a
straight push along the table (world metres) or push_image() one given in pixels. The simulated
robot is the one implementation bound (a real arm implements the same C++ interface)."""

from .sim import SimulatedRobot, TableOptions

Robot = SimulatedRobot

__all__ = ["Robot", "SimulatedRobot", "TableOptions"]
