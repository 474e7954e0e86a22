"""The testbench: MuJoCo machines wired to mcl axes, scene builders, demo programs and a CLI."""
