; heating and extruding with T1 of a two-tool printer when only T0's material (pla-paper) is given
; printer: prusa-xl-2t
; expect: tool-without-material 6
M140 S55 ; bed
M104 S190 ; T0
M104 T1 S225 ; <-- unsafe: no material to judge T1 by
G28 ; home
M190 S55
G90
M83 ; relative E
G92 E0
G1 Z0.2 F600
G1 X20 Y20 F3000
G1 X60 Y20 E1.5 F1200
T1
G1 X100 Y20 E1.5 F1200
T0
G1 Z10 F600
M104 S0
M104 T1 S0
M140 S0
M84
