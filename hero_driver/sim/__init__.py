"""The simulated HERO 2000: a pymunk world with sonar, grasps and an overhead camera
(docs/simulator.md). The driver facade is ``hero_driver.sim_driver.SimulatedHero``."""
