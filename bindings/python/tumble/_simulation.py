class Simulation: pass
