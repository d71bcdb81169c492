// Agent faulty on a mission (issue 38): it visits its waypoints in order; when a motion fails it
// runs the cooperative diagnosis (agents/diagnosis/faulty.asl, included below) and recovers
// from what the diagnosis names, as a MAPE-K loop over its beliefs:
//   Monitor  a motion of the task fails (-!mission[error(R)]: no_progress, bad_move, ...);
//   Analyze  the cooperative diagnosis names the component (diagnosis(D));
//   Plan     a strategy is chosen from D (strategy/2, recovery(S));
//   Execute  the strategy runs: delegate the remaining waypoints to Helper (a contract: offer,
//            accept, done ... finished), retry on its own, or give the mission up with a reason.
//   Knowledge: waypoint(I, X, Y) (percepts: the task), reached(I, By), diagnosis(D),
//            recovery(S), delegated(H), gaveUp(Why), missionDone.
// The runner (rason_diagnosis.mission) reads these beliefs through the mind service.

// ---- Plan: the strategy for each diagnosis. A named fault: Helper takes the remaining
// waypoints over (limp mode for one actuator and a reference from Helper for odometry are not
// written yet; until then delegation covers them). A false positive: go on alone. Unknown: go
// on alone once, then delegate.
strategy(both_actuators, delegate).
strategy(odometry, delegate).
strategy(left_actuator, delegate).
strategy(right_actuator, delegate).
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

// ---- Monitor: a motion of the task failed.
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
+!analyze(R)
   : R == no_progress | R == bad_move
   <- -diagnosis(_);
      -+reason(R);
      .print("ANALYZE: ", R, ": asking for help to diagnose it");
      .broadcast(achieve, helpme);
      .wait(diagnosis(_)).
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
// The contract: offer the remaining waypoints, saying where Faulty stands (by its odometry, so
// Helper drives around it); Helper accepts (or refuses), tells done(I) per waypoint and finished
// at the end (or failed(R)).
+!execute(delegate)
   : remaining(Ws) & helperOf(H) & pose(X, Y, _)
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
