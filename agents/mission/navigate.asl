// Navigation to a point of the room by odometry (issue 38's missions), for Faulty and Helper.
// Included by agents/mission/faulty.asl and helper.asl, whose included diagnosis agents define
// wrap/2 (angles into (-180, 180]).
// Percepts (rason_diagnosis' pose_synthesizer, from the robot's own odometry):
//   pose(X, Y, Yaw)   world frame: m, degrees counter-clockwise
//   heading(H)        the same heading as turn_to reads one (odometry frame, positive clockwise)

arrivalTolerance(0.1).  // m: a point is reached closer than this (by odometry)
maxLegs(3).             // turn_to + move legs tried before a point counts as not reached
poseWait(500).          // ms after a move before the pose is read again (percepts at 5 Hz)

distanceTo(X, Y, D)
   :- pose(X0, Y0, _) & D = math.sqrt((X - X0) * (X - X0) + (Y - Y0) * (Y - Y0)).
// The world bearing (degrees, counter-clockwise) of (X, Y) at distance D > 0 from the pose.
bearingTo(X, Y, D, B)
   :- pose(X0, Y0, _) & C = math.max(-1, math.min(1, (X - X0) / D))
    & S = math.acos(C) * 180 / 3.14159265 & ((Y >= Y0 & B = S) | (Y < Y0 & B = -S)).
// One leg: the turn_to heading H that faces (X, Y), and the distance D to it.
legTo(X, Y, H, D)
   :- distanceTo(X, Y, D) & bearingTo(X, Y, D, B) & pose(_, _, Yaw) & heading(H0)
    & wrap(B - Yaw, T) & wrap(H0 - T, HW) & H = math.round(HW * 10) / 10.

+!goto(X, Y) : maxLegs(N) <- !leg(X, Y, N).

+!leg(X, Y, _) : distanceTo(X, Y, D) & arrivalTolerance(E) & D < E.
+!leg(X, Y, 0) <- .fail(error(not_arrived)).
+!leg(X, Y, N)
   : legTo(X, Y, H, D) & poseWait(W)
   <- turn_to(H);
      move(math.round(D * 1000) / 1000);
      .wait(W);
      !leg(X, Y, N - 1).
