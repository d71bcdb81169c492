// Agent faulty on a mission (issue 38): it visits its waypoints in order; when a motion fails it
// runs the cooperative diagnosis (agents/diagnosis/faulty.asl, included below) and recovers
// from what the diagnosis names, as a MAPE-K loop over its beliefs:
//   Monitor  a motion of the task fails (-!mission[error(R)]: no_progress, bad_move, ...);
//   Analyze  the cooperative diagnosis names the component (diagnosis(D));
//   Plan     a strategy is chosen from D (strategy/2, recovery(S));
//   Execute  the strategy runs: limp on (learn how the base moves now, set the motion
//            decomposer for it), drive open loop guided by Helper's sightings (a frozen
//            encoder), delegate the remaining waypoints to Helper (a contract: offer, accept,
//            done ... finished), retry on its own, or give the mission up with a reason.
//   Knowledge: waypoint(I, X, Y) (percepts: the task), reached(I, By), diagnosis(D),
//            recovery(S), limping(K, G, A), guidedBy(H), fix(X, Y, Yaw), delegated(H),
//            gaveUp(Why), missionDone.
// The runner (rason_diagnosis.mission) reads these beliefs through the mind service.

// ---- Plan: the strategy for each diagnosis. One weak wheel: limp on (a second failure while
// limping: delegate). Both wheels: Helper takes the remaining waypoints over. The odometry:
// drive open loop, located by Helper's Kinect (guided; when Helper cannot locate Faulty:
// delegate). A false positive: go on alone. Unknown: go on alone once, then delegate.
strategy(both_actuators, delegate).
strategy(odometry, guided) :- not guidedBy(_) & not unguidedBecause(_).
strategy(odometry, delegate) :- guidedBy(_) | unguidedBecause(_).
strategy(left_actuator, limp) :- not limping(_, _, _).
strategy(right_actuator, limp) :- not limping(_, _, _).
strategy(left_actuator, delegate) :- limping(_, _, _).
strategy(right_actuator, delegate) :- limping(_, _, _).
strategy(false_positive, retry).
strategy(unknown, retry) :- not retried.
strategy(unknown, delegate) :- retried.

// The first waypoint not reached yet, and every one not reached (for an offer).
nextWaypoint(I, X, Y)
   :- .findall(J, waypoint(J, _, _) & not reached(J, _), L) & L \== [] & .min(L, I)
    & waypoint(I, X, Y).
remaining(Ws) :- .findall(wp(I, X, Y), waypoint(I, X, Y) & not reached(I, _), Ws).
// Who helped in the diagnosis (it told found(...)); else the case study's helper.
helperOf(H) :- found(_)[source(H)].
helperOf(helper) :- not found(_).

// Before the diagnosis' plans (included at the end): this +!start wins over its own.
+!start <- .wait(4000); !mission.

// ---- Execute the task
+!mission : gaveUp(_).
+!mission
   : delegated(_) & nextWaypoint(_, _, _)
   <- .wait(1000);                                // Helper is driving them (done(I) below)
      !mission.
+!mission
   : not delegated(_) & nextWaypoint(I, X, Y)
   <- .print("going to waypoint ", I, " (", X, ", ", Y, ")");
      !goto(X, Y);
      +reached(I, faulty);
      .print("reached waypoint ", I);
      !mission.
+!mission
   : waypoint(_, _, _)
   <- .print("mission complete");
      +missionDone.
+!mission <- .wait(500); !mission.                // the task is not perceived yet

// ---- Monitor: a motion of the task failed. Guided, a failure (Helper could not locate Faulty,
// a point not reached in its legs, a bumper) is not the odometry's again: delegate, saying why.
-!mission[error(R)]
   : guidedBy(_) & not gaveUp(_)
   <- .print("MONITOR: a guided leg failed: ", R);
      !unguide(R);
      !mission.
-!mission[error(R)]
   : not gaveUp(_)
   <- .print("MONITOR: a motion of the mission failed: ", R);
      !analyze(R);
      ?diagnosis(D);
      !plan(D);
      ?recovery(S);
      !execute(S);
      !mission.
-!mission[error(R)] <- .print("mission over (", R, ")").

// ---- Analyze: the cooperative diagnosis (its plans decide on reason(R) and Helper's feedback).
// Helper's answers to an earlier diagnosis are dropped first: told again, an answer already
// believed would bring no event (+found, +notFound), and Faulty would wait for it in vain; so
// is the earlier diagnosis' 90 s wait for an answer (!awaitHelp), which would otherwise end
// this one `unknown` 90 s after the first began.
+!analyze(R)
   : R == no_progress | R == bad_move
   <- -diagnosis(_);
      .drop_desire(awaitHelp);
      .abolish(found(_));
      .abolish(notFound(_));
      -+reason(R);
      .print("ANALYZE: ", R, ": asking for help to diagnose it");
      !aimHelper;
      .broadcast(achieve, helpme);
      .wait(diagnosis(_)).
// Helper first turns to face where Faulty's pose puts it (after an odometry fault, where the
// encoder froze: a few tenths of a metre off), so that its search starts with Faulty in view
// instead of sweeping past it when its camera's frames come slowly. Its answer looking(X, Y)
// is awaited aimWait at most (no answer: the search sweeps as before).
aimWait(15000).         // ms
+!aimHelper
   : here(X, Y, _) & aimWait(T)
   <- .abolish(looking(_, _));
      .broadcast(achieve, lookAt(X, Y));
      .wait(looking(_, _), T, _).
+!aimHelper.
+!analyze(R)
   <- .print("ANALYZE: ", R, " is not a failure the diagnosis reads");
      -+unknownBecause(R);
      -+diagnosis(unknown).

// ---- Plan
+!plan(D)
   : mission_option(no_recovery)
   <- .print("PLAN: diagnosis ", D, "; recovery is off (--no-recovery)");
      -+recovery(none).
+!plan(D)
   : strategy(D, S)
   <- .print("PLAN: diagnosis ", D, ": recovery ", S);
      -+recovery(S).
+!plan(D)
   <- .print("PLAN: no strategy for diagnosis ", D);
      -+recovery(none).

// ---- Execute
+!execute(none)
   : mission_option(no_recovery)
   <- !giveUpMission(no_recovery).
+!execute(none)
   : diagnosis(D)
   <- !giveUpMission(no_strategy(D)).
+!execute(retry)
   <- +retried;
      .print("EXECUTE: going on alone").
// Limp mode (one weak wheel; its encoders are right, so the odometry still is): learn how
// the base moves now from a test move and a test turn driven open loop (the motion
// decomposer's configure(reference, command): it commands what a healthy base would need and
// stops by its own dead reckoning), read by odometry: the curvature K (rad/m, + left) of a
// straight command, and the base's speed (G) and turn rate (A) over the commanded ones. Then
// the decomposer is set for them: each move turns first and drives the arc of curvature K
// whose chord is the move, at compensated speeds; navigate.asl keeps each leg to limpLeg(L),
// 80% of the longest such chord. A base that cannot be driven this way: delegate instead.
testMove(0.3).          // m, open loop
testTurn(-60).          // deg (left), open loop
limpGains(X0, Y0, A0, X1, Y1, A1, A2, K, G, A)
   :- testMove(M) & testTurn(T) & C = math.sqrt((X1 - X0) * (X1 - X0) + (Y1 - Y0) * (Y1 - Y0))
    & wrap(A1 - A0, DA) & R = DA * 3.14159265 / 180 & arcLength(C, R, S)
    & K = math.round(R / S * 1000) / 1000 & G = math.round(S / M * 1000) / 1000
    & wrap(A2 - A1, DT) & A = math.round(-DT / T * 1000) / 1000.
arcLength(C, R, C) :- math.abs(R) < 0.01.
arcLength(C, R, S) :- math.abs(R) >= 0.01 & S = C * (R / 2) / math.sin(R / 2).
limpLegFor(K, L) :- math.abs(K) > 0.8 & L = math.round(1600 / math.abs(K)) / 1000.
limpLegFor(K, 2) :- math.abs(K) <= 0.8.

+!execute(limp)
   : testMove(M) & testTurn(T) & poseWait(W)
   <- .print("EXECUTE: limp mode: a test move and turn, open loop, to learn how I move now");
      configure(reference, command);
      .wait(W);
      ?pose(X0, Y0, A0);
      move(M);
      .wait(W);
      ?pose(X1, Y1, A1);
      turn(T);
      .wait(W);
      ?pose(_, _, A2);
      configure(reference, odom);
      ?limpGains(X0, Y0, A0, X1, Y1, A1, A2, K, G, A);
      ?limpLegFor(K, L);
      .print("EXECUTE: limp mode: curvature ", K, " rad/m, speed gain ", G, ", turn gain ", A, ", legs up to ", L, " m");
      configure(curvature, K);
      configure(linear_gain, G);
      configure(angular_gain, A);
      -+limpLeg(L);
      +limping(K, G, A).
-!execute(limp)[error(R)]
   <- .print("EXECUTE: limp mode failed (", R, "): delegating instead");
      configure(reference, odom);
      configure(curvature, 0);
      -limpLeg(_);
      +limping(failed, 0, 0);
      -+recovery(delegate);
      !execute(delegate).

// Guided mode (a frozen encoder; the wheels work): the motion decomposer drives open loop
// (configure(reference, command): it stops by its own dead reckoning of the commands), and
// Faulty navigates by fix(X, Y, Yaw), where Helper's Kinect puts it (navigate.asl prefers it to
// the frozen pose/3): a fix before the first leg and after every leg of at most guidedLeg, until
// a fix is within arrivalTolerance of the waypoint. Faulty asks whereAmI(X, Y), where it expects
// to be (Helper faces that point first: a leg may take Faulty out of its view); Helper answers
// located(X, Y, Yaw, HX, HY) (HX, HY: where Helper stands, kept clear as avoid/2), with the
// colour of the one cylinder seen in place of Yaw when the other is hidden, or with
// notLocated(Why). The fix's heading: the direction travelled since the last fix after a leg of
// trackLeg or more (what the base really did), else the yaw Helper saw, else the course turned
// to; a lone cylinder's centre is put from that course (green on the left, orange on the right).
guidedLeg(1.5).         // m: the longest open-loop leg between two fixes
trackLeg(0.8).          // m: a leg at least this long gives the heading by the direction travelled
fixWait(60000).         // ms: Helper's answer to whereAmI (a search may take a full sweep)
cylinderOffset(0.1135). // m: each cylinder beside the centre (turtlebot_sim's Faulty)
travelled(X, Y, A)
   :- legFrom(X0, Y0, M) & trackLeg(L) & M >= L
    & D = math.sqrt((X - X0) * (X - X0) + (Y - Y0) * (Y - Y0)) & D >= L / 2
    & bearingFrom(X0, Y0, X, Y, D, A).
fixCentre(X, Y, A, X, Y) :- .number(A).
fixCentre(X, Y, green, CX, CY)
   :- course(B) & cylinderOffset(O) & R = B * 3.14159265 / 180
    & CX = X + O * math.sin(R) & CY = Y - O * math.cos(R).
fixCentre(X, Y, orange, CX, CY)
   :- course(B) & cylinderOffset(O) & R = B * 3.14159265 / 180
    & CX = X - O * math.sin(R) & CY = Y + O * math.cos(R).
fixYaw(X, Y, _, A) :- travelled(X, Y, A).
fixYaw(X, Y, A, A) :- not travelled(X, Y, _) & .number(A).
fixYaw(X, Y, C, A) :- not travelled(X, Y, _) & .atom(C) & course(A).
fixOf(X0, Y0, A0, X, Y, A)
   :- fixCentre(X0, Y0, A0, CX, CY) & fixYaw(CX, CY, A0, CA)
    & X = math.round(CX * 1000) / 1000 & Y = math.round(CY * 1000) / 1000
    & A = math.round(CA * 10) / 10.

+!execute(guided)
   : helperOf(H)
   <- .print("EXECUTE: guided: my odometry is frozen; driving open loop, located by ", H);
      configure(reference, command);
      -legFrom(_, _, _);
      -course(_);
      +guidedBy(H);
      !fixFrom(H).
-!execute(guided)[error(R)] <- !unguide(R).

// Where Faulty expects to be: the last leg's end (its start, course and length), else here.
expected(X, Y)
   :- legFrom(X0, Y0, L) & course(B) & R = B * 3.14159265 / 180
    & X = math.round((X0 + L * math.cos(R)) * 1000) / 1000
    & Y = math.round((Y0 + L * math.sin(R)) * 1000) / 1000.
expected(X, Y) :- not legFrom(_, _, _) & here(X, Y, _).

+!fixFrom(H)
   : fixWait(T) & poseWait(W) & expected(X, Y)
   <- .abolish(located(_, _, _, _, _));
      .abolish(notLocated(_));
      .wait(W);                                   // the base at rest before Helper looks
      .send(H, achieve, whereAmI(X, Y));
      .wait(located(_, _, _, _, _) | notLocated(_), T);
      !takeFix(H).

+!takeFix(H)
   : located(X0, Y0, A0, HX, HY)[source(H)] & fixOf(X0, Y0, A0, X, Y, A)
   <- .abolish(located(_, _, _, _, _));
      -+fix(X, Y, A);
      -+avoid(HX, HY);
      .print("GUIDED: ", H, " sees me at (", X, ", ", Y, "), heading ", A).
// One cylinder seen and no course to place the centre by (the first fix): turn to show the
// other flank and ask again, once.
+!takeFix(H)
   : located(_, _, C, _, _)[source(H)] & .atom(C) & not flankShown & flankTurn(T)
   <- +flankShown;
      .print("GUIDED: ", H, " sees only my ", C, " cylinder: turning ", T, " degrees");
      turn(T);
      -legFrom(_, _, _);
      !fixFrom(H).
// (.fail's error is an atom: a structured one would come back as internal_action.)
+!takeFix(H)
   : notLocated(Why)[source(H)]
   <- .print("GUIDED: ", H, " could not locate me: ", Why);
      .fail(error(not_located)).
+!takeFix(H) <- .fail(error(no_heading)).

// Helper could not locate Faulty (or a guided leg failed): delegate the rest, saying why.
+!unguide(R)
   <- .print("EXECUTE: guided mode failed (", R, "): delegating instead");
      -guidedBy(_);
      -avoid(_, _);
      -+unguidedBecause(R);
      -+recovery(delegate);
      !execute(delegate).

// The contract: offer the remaining waypoints, saying where Faulty stands (by its last fix, else
// its odometry, so Helper drives around it); Helper accepts (or refuses), tells done(I) per
// waypoint and finished at the end (or failed(R)).
+!execute(delegate)
   : remaining(Ws) & helperOf(H) & here(X, Y, _)
   <- .print("EXECUTE: offering waypoints ", Ws, " to ", H);
      +delegated(H);
      .send(H, achieve, offer(Ws, at(X, Y))).

+accept(Ws)[source(H)] : delegated(H) <- .print(H, " accepted waypoints ", Ws).
+refuse(Why)[source(H)]
   : delegated(H)
   <- -delegated(H);
      !giveUpMission(refused(H, Why)).
+done(I)[source(H)]
   : delegated(H)
   <- +reached(I, H);
      .print(H, " reached waypoint ", I).
+failed(R)[source(H)]
   : delegated(H)
   <- -delegated(H);
      !giveUpMission(delegate_failed(R)).
+finished[source(H)] <- .print(H, " finished the waypoints it took over").

+!giveUpMission(Why)
   <- .print("giving the mission up: ", Why);
      -+gaveUp(Why).

{ include("navigate.asl") }
{ include("../diagnosis/faulty.asl") }
