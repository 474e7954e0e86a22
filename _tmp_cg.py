from scenes import gantry

scene = gantry.build(start={"X": 0.43, "Y": 0.27, "Z": -0.12}, trace_every=0)
program = gantry.Demo(scene)
scene.run(program, timeout=6.0)  # power, homing, into the path
print(program.step)
