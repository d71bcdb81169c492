// Drive a 0.5 m square: four sides, each a move and a right turn (README, "Ten lines of .asl").
side(0).

!square.

+!square : side(4) <- .print("square done").
+!square : side(N) <- move(0.5); turn(90); -+side(N + 1); !square.

-!square[error(E)] <- .print("square stopped: ", E).
