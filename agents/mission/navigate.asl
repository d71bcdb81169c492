// Navigation to a point of the room by odometry (issue 38's missions), for Faulty and Helper.
// Included by agents/mission/faulty.asl and helper.asl, whose included diagnosis agents define
// wrap/2 (angles into (-180, 180]).
// Percepts (rason_diagnosis' pose_synthesizer, from the robot's own odometry):
//   pose(X, Y, Yaw)   world frame: m, degrees counter-clockwise
//   heading(H)        the same heading as turn_to reads one (odometry frame, positive clockwise)
// A robot whose odometry is frozen navigates by fix(X, Y, Yaw) instead (the same frame and
// units: where Helper saw it; agents/mission/faulty.asl's guided mode): while guidedBy(H), each
// leg is a relative turn and an open-loop move, then a new fix from H (!fixFrom(H)).

arrivalTolerance(0.1).  // m: a point is reached closer than this (by odometry)
maxLegs(3).             // turn_to + move legs tried before a point counts as not reached
poseWait(500).          // ms after a move before the pose is read again (percepts at 5 Hz)
clearance(0.8).         // m between centres kept from avoid(X, Y), a stopped robot, when passing
standOff(0.45).         // m between centres at least, when a point is next to it (bodies: 0.354)

// Where the robot is: the last fix when it has one, else its odometry's pose.
here(X, Y, Yaw) :- fix(X, Y, Yaw).
here(X, Y, Yaw) :- not fix(_, _, _) & pose(X, Y, Yaw).

// A leg's move: the whole distance, or at most legCap(C): limpLeg (a base that curves by itself
// reaches a point ahead only by an arc, and no arc reaches far) or, guided, guidedLeg (an
// open-loop move between two fixes) (agents/mission/faulty.asl); the legs allowed for a point:
// maxLegs, plus one per legCap of the distance.
legCap(C) :- limpLeg(C).
legCap(C) :- not limpLeg(_) & guidedBy(_) & guidedLeg(C).
legLength(D, L) :- legCap(C) & L = math.min(D, C).
legLength(D, D) :- not legCap(_).
legBudget(X, Y, N) :- maxLegs(N0) & legCap(C) & distanceTo(X, Y, D) & N = N0 + math.ceil(D / C).
legBudget(_, _, N) :- maxLegs(N) & not legCap(_).

distanceTo(X, Y, D)
   :- here(X0, Y0, _) & D = math.sqrt((X - X0) * (X - X0) + (Y - Y0) * (Y - Y0)).
// The world bearing (degrees, counter-clockwise) of (X, Y) at distance D > 0 from here, or
// from (X0, Y0).
bearingTo(X, Y, D, B) :- here(X0, Y0, _) & bearingFrom(X0, Y0, X, Y, D, B).
bearingFrom(X0, Y0, X, Y, D, B)
   :- C = math.max(-1, math.min(1, (X - X0) / D))
    & S = math.acos(C) * 180 / 3.14159265 & ((Y >= Y0 & B = S) | (Y < Y0 & B = -S)).
// One leg: the turn_to heading H that faces (X, Y), and the distance D to it.
legTo(X, Y, H, D)
   :- distanceTo(X, Y, D) & bearingTo(X, Y, D, B) & here(_, _, Yaw) & heading(H0)
    & wrap(B - Yaw, T) & wrap(H0 - T, HW) & H = math.round(HW * 10) / 10.

// A detour: when the straight line to (X, Y) passes closer than the clearance to avoid(OX, OY),
// first to the via point at the clearance from it, square to the line (or on the line's left
// when the line runs through it).
viaPoint(X, Y, OX, OY, VX, VY)
   :- here(X0, Y0, _) & DX = X - X0 & DY = Y - Y0 & L2 = DX * DX + DY * DY & L2 > 0
    & T = ((OX - X0) * DX + (OY - Y0) * DY) / L2 & T > 0 & T < 1
    & QX = X0 + T * DX & QY = Y0 + T * DY
    & E = math.sqrt((QX - OX) * (QX - OX) + (QY - OY) * (QY - OY)) & clearance(C) & E < C
    & awayFrom(QX - OX, QY - OY, E, DX, DY, UX, UY)
    & VX = math.round((OX + C * UX) * 1000) / 1000 & VY = math.round((OY + C * UY) * 1000) / 1000.
awayFrom(EX, EY, E, _, _, UX, UY) :- E > 0.05 & UX = EX / E & UY = EY / E.
awayFrom(_, _, E, DX, DY, UX, UY)
   :- E <= 0.05 & L = math.sqrt(DX * DX + DY * DY) & UX = -DY / L & UY = DX / L.

// A point closer than standOff to the stopped robot: the nearest point standOff from it.
standIn(X, Y, OX, OY, SX, SY)
   :- standOff(S) & D = math.sqrt((X - OX) * (X - OX) + (Y - OY) * (Y - OY)) & D < S & D > 0.01
    & SX = math.round((OX + (X - OX) * S / D) * 1000) / 1000
    & SY = math.round((OY + (Y - OY) * S / D) * 1000) / 1000.

+!goto(X, Y)
   : avoid(OX, OY) & standIn(X, Y, OX, OY, SX, SY)
   <- .print("(", X, ", ", Y, ") is next to the robot at (", OX, ", ", OY, "): going to (", SX, ", ", SY, ")");
      !route(SX, SY).
+!goto(X, Y) <- !route(X, Y).

// The line from a via point to (X, Y) is checked again (it may still pass close: above all to
// a stand-in point next to the stopped robot), at most maxDetours via points in all, so that a
// route goes round the robot on the clearance's circle in steps.
maxDetours(3).
+!route(X, Y) : maxDetours(K) <- !route(X, Y, K).
+!route(X, Y, K)
   : K > 0 & avoid(OX, OY) & viaPoint(X, Y, OX, OY, VX, VY) & maxLegs(N)
   <- .print("detour by (", VX, ", ", VY, ") around (", OX, ", ", OY, ")");
      !leg(VX, VY, N);
      !route(X, Y, K - 1).
+!route(X, Y, _) : legBudget(X, Y, N) <- !leg(X, Y, N).

+!leg(X, Y, _) : distanceTo(X, Y, D) & arrivalTolerance(E) & D < E.
+!leg(X, Y, 0) <- .fail(error(not_arrived)).
// Guided (frozen odometry): turn by the fix's heading to face (X, Y), drive open loop, then
// ask for a new fix; course(B) and legFrom(X0, Y0, L) tell the next fix's plans the heading
// the robot should have and where the move started.
+!leg(X, Y, N)
   : guidedBy(H) & here(X0, Y0, Yaw) & distanceTo(X, Y, D) & bearingTo(X, Y, D, B)
   & legLength(D, L) & wrap(Yaw - B, T)
   <- turn(math.round(T * 10) / 10);
      -+course(B);
      -+legFrom(X0, Y0, L);
      move(math.round(L * 1000) / 1000);
      !fixFrom(H);
      !leg(X, Y, N - 1).
+!leg(X, Y, N)
   : legTo(X, Y, H, D) & legLength(D, L) & poseWait(W)
   <- turn_to(H);
      move(math.round(L * 1000) / 1000);
      .wait(W);
      !leg(X, Y, N - 1).
