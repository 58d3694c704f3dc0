; a corner of the square that a round 200 mm bed lacks
; expect: outside-bed 13
; printer: generic-delta
M140 S55
M104 S190
G28
M190 S55
M109 S190
G90
M83
G1 X0 Y0 Z0.2 F3000
G1 X40 Y0 E1.5 F1200
G1 X80 Y80 F3000 ; <-- unsafe
G1 Z10 F600
M104 S0
M140 S0
M84
