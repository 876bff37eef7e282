# Compensation tables for the sim mill (docs/compensation.md): an example
# of what a calibration writes (sh2000-comp), not a calibration of the
# simulated machine. Load it with [SH2000]COMP in sh2000-sim.ini (hal_sh2000
# loads it before the servo thread runs) or sh2000ctl comp load.
id 0x5a2000c0
pitch X                    # position (mm), correction (mm)
0    0.000
150  0.003
300  0.005
450  0.004
600  0.006
pitch Y                    # LinuxCNC's comp-file form: nominal forward reverse
0     0.000     0.000
300 299.998   299.998
600 599.996   599.996
