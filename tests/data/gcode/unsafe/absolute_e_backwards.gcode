; absolute E sent 8 mm back without G92 (a retraction is 2 mm)
; expect: e-backwards 15
M140 S55 ; bed
M104 S190 ; nozzle
G28 ; home
M190 S55
M109 S190
G90
M82 ; absolute E
G92 E0
G1 Z0.2 F600
G1 X20 Y20 F3000
G1 X60 Y20 E1.5 F1200
G1 X100 Y20 E3 F1200
G1 E-5 F2400 ; <-- unsafe
G1 Z10 F600
M104 S0
M140 S0
M84
