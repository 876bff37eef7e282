# SH-2000 compensation tables of a small machine (docs/compensation.md).
# Positions and corrections in mm; the correction is added to the nominal
# set-point.
id 0x20261127

# X's scale reads 30 um/m long: command a little further
pitch X
-10 0.0000
0 0.0003
100 0.0033
200 0.0063
300 0.0093
310 0.0096

# LinuxCNC's comp-file form: nominal, forward, reverse
pitch Y
-10 -10.0002 -10.0002
0 0 0
150 149.9985 149.9987
300 299.9971 299.9973
310 309.9970 309.9972

# Y's guide leans 50 urad towards +X
square X Y -50e-6

# X's guide bows 3 um in Y over its travel
cross Y X
0 0
100 -0.0027
150 -0.0030
200 -0.0027
300 0

# the X-Y plane's flatness in Z, a 3 x 3 grid of 150 mm
grid Z X Y 0 150 3 0 150 3
0 -0.001 0
-0.001 -0.002 -0.001
0 -0.001 0
