; extruding with a second tool on a printer that has one
; expect: unknown-tool 14
M140 S55 ; bed
M104 S190 ; nozzle
G28 ; home
M190 S55
M109 S190
G90
M83 ; relative E
G92 E0
G1 Z0.2 F600
G1 X20 Y20 F3000
G1 X60 Y20 E1.5 F1200
T1 ; <-- unsafe: generic-marlin has T0 only
G1 X100 Y20 E1.5 F1200
T0
G1 Z10 F600
M104 S0
M140 S0
M84
