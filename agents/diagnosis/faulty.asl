// Agent faulty: thesis (Morais 2015) Appendix A.1, with ONLY the fixes documented in
// docs/thesis-fixes.md of the rason repository. Every change is marked "FIX(Fn):", Fn its entry.
// Added for testability (not a thesis fix): a belief diagnosis(D) recording the outcome,
// D in both_actuators, odometry, left_actuator, right_actuator, false_positive, unknown,
// no_fault. Those lines are marked "ADDED:".
// Added for robots on their own machines (not a thesis fix): handling of a .send to an
// unreachable Helper and of an answer that never comes (docs/deployment.md, "Link faults"). Marked "HOSTS:".

/* Initial beliefs and rules */

// Evidence margins (FIX(F4), FIX(F5): see the feedback plans below).
turnLimit(8).           // deg: the thesis' bad_move threshold
turnMargin(3).          // deg: a side is named beyond turnLimit + margin, none below - margin
movedLimit(0.08).       // m: displaced more than this (plus the partial slack): Faulty moved
stillLimit(0.04).       // m: displaced less than this: Faulty did not move
partialSlack(0.12).     // m: a single cylinder stands up to 11.35 cm from Faulty's centre
flankTurn(60).          // deg: turn that shows Helper a flank when the heading is hidden

// FIX(F8): every angle difference is wrapped into (-180, 180]: the thesis' rule
// Yaw1 - (Yaw + (Deg1 - Deg)) read 178.4 -> -167.9 (a 13.7 degree right turn) as -344.8.
wrap(A, W) :- W = A - 360 * math.ceil((A - 180) / 360).

// The turn Faulty made between the two sightings (yaw = heading + bearing, so the heading
// change is the yaw change minus the bearing change), less any turn it made on purpose.
turnSeen(initPos(D, _, Y), currPos(D1, _, Y1), Turn)
   :- turned(T0) & wrap(D1 - D, DA) & wrap(Y1 - Y - DA - T0, W) & Turn = math.round(W * 10) / 10.
turned(T) :- turnedBy(T).
turned(0) :- not turnedBy(_).

// Where a sighting puts Faulty in Helper's camera plane (x right, z forward), and what it is:
// full (the centre) or the colour of the one cylinder seen.
place(initPos(D, Dp, _), D, Dp, full) :- true.
place(initPart(D, Dp, C), D, Dp, C) :- true.
place(currPos(D, Dp, _), D, Dp, full) :- true.
place(currPart(D, Dp, C), D, Dp, C) :- true.
slack(K, K, 0) :- true.
slack(K0, K1, S) :- K0 \== K1 & partialSlack(S).
displacement(Init, Curr, Dist, Slack)
   :- place(Init, D0, Dp0, K0) & place(Curr, D1, Dp1, K1) & slack(K0, K1, Slack)
    & X0 = Dp0 * math.tan(D0 * 3.14159265 / 180) & X1 = Dp1 * math.tan(D1 * 3.14159265 / 180)
    & Dist = math.round(math.sqrt((X1 - X0) * (X1 - X0) + (Dp1 - Dp0) * (Dp1 - Dp0)) * 1000) / 1000.

// A turn away from the occlusion angle (heading - bearing = +90 as Helper sees it), and
// whether a sighting's heading is near it (there the yaw is off by up to ~6 degrees).
awayTurn(initPos(D, _, Y), T) :- wrap(Y - 2 * D - 90, E) & E >= 0 & flankTurn(T).
awayTurn(initPos(D, _, Y), T) :- wrap(Y - 2 * D - 90, E) & E < 0 & flankTurn(F) & T = -F.
awayTurn(currPos(D, _, Y), T) :- awayTurn(initPos(D, 0, Y), T).
weakView(currPos(D, _, Y)) :- wrap(Y - 2 * D - 90, E) & occlusionMargin(M) & math.abs(E) < M.
occlusionMargin(20).

/* Initial goals */

!start.

/* Plans */

+!start <- .wait(4000); !goToDestination.

+!goToDestination
   <- .print("Moving to Destination");
      move(1);
      move(-1);
      .print("Arriving at destination");
      -+diagnosis(no_fault).                                  // ADDED: outcome belief

// FIX(F1): the heads matched the reason as the first annotation ([R1 | Rest]); in Jason the
// failure annotations are sorted (code, code_line, error, error_msg, ...), so the reason is
// now matched explicitly as error(R).
// FIX(F13): a reason the diagnosis does not read (no_decomposer, action_timeout,
// decomposer_lost... : no motion was judged) ends the run unknown, saying why, once. As printed,
// the last plan below passed it to !diagnoseAlone, which has no plan for it; that failure ran
// this failure plan again, each time with no_applicable, for ever.
-!goToDestination[error(R)]
   : R \== no_progress & R \== bad_move                       // FIX(F13): !diagnoseAlone's reasons
   <- .print("something went wrong...", R, ": not a fault the diagnosis reads");
      !giveUp(R).

-!goToDestination[error(R)]
   : triedAlone
   <- .print("Cannot solve problem alone, asking for help.");
      +reason(R);
      .broadcast(achieve, helpme).

-!goToDestination[error(R)]                                   // FIX(F1): was [R1 | Rest]
   <- .print("something went wrong...", R);
      !diagnoseAlone([R]);                                    // FIX(F1): was [R1 | Rest]
      !goToDestination.

+!diagnoseAlone(Reasons)
   : .member(no_progress, Reasons)
   | .member(bad_move, Reasons)
   <- .print("Running local diagnosis");
      .print("diagnose alone has failed");
      +triedAlone;
      .print("Finished diagnosis").

//Plans to help diagnose
+!tryMove[source(R)]
   <- .print("Trying to move for ", R);
      -turnedBy(_);
      move(0.3);
      .print("It was just a false positive.");
      -reason(_);
      -triedAlone;
      -+diagnosis(false_positive);                            // ADDED: outcome belief
      .send(R, achieve, thanks).

-!tryMove[source(R)]
   <- .print(" requesting some feedback from ", R);
      !ask(R, achieve, giveFeedback).                         // FIX(F2): was givemeFeedback; HOSTS: !ask

+found(Me)[source(R)]
   : .my_name(Me)
   <- .print(R, " found me, asking to track me");
      !ask(R, achieve, trackMe).                              // HOSTS: was .send, see !ask

// FIX(F6): Helper gives up after a full turn (or after losing sight of us) and tells us so; we
// report unknown, saying why.
+notFound(Me)[source(R)]
   : .my_name(Me)
   <- .print(R, " could not find me: the fault is unknown");
      -+unknownBecause("the helper could not find me or keep me in view");
      -+diagnosis(unknown).                                   // ADDED: outcome belief

// HOSTS (robots on their own machines, ./run.sh demo --hosts --cut ...): a .send fails with
// error(ia_failed) and the reason in error_msg when the receiver's presence has lapsed (its link
// is down). Without Helper the diagnosis cannot go on: it ends unknown with that reason, never
// with a guessed component. !ask is a .send whose failure the plan handles.
+!ask(R, Performative, Content) <- .send(R, Performative, Content).
-!ask(R, Performative, Content)[error(ia_failed), error_msg(Why)]
   <- .print("cannot reach ", R, ": ", Why);
      !giveUp(Why).

// HOSTS: Helper's answer may never come (its link, or ours, down while it answered): 90 s
// after asking for help without a diagnosis, it ends unknown with that reason. (!! : the
// wait runs beside the plan that added reason(R), which goes on to ask for help.)
+reason(_) <- !!awaitHelp.
+!awaitHelp
   <- .wait(90000);
      !giveUp("no answer from a helper within 90 s").

+!giveUp(Why)
   : not diagnosis(_)
   <- .print("the fault is unknown: ", Why);
      +unknownBecause(Why);
      -+diagnosis(unknown).                                   // ADDED: outcome belief
+!giveUp(_).

// FIX(F11) (future work of the thesis: against self-occlusion): Helper cannot see our heading
// (one cylinder hides the other); we turn to show it a flank, then it looks again.
+!showFlank(T)[source(R)]
   <- .print("turning ", T, " degrees to show ", R, " my flank");
      turn(T);
      !ask(R, achieve, trackMe).                              // HOSTS: !ask

-!showFlank(_)[source(R)]
   <- .print("could not turn as ", R, " asked; it looks again anyway");
      !ask(R, achieve, trackMe).                              // HOSTS: !ask

// FIX(F3) (all feedback plans): the prints used the unbound variable Helper; it is R.
// FIX(F4), FIX(F5), FIX(F10) (never a wrong component): the thesis named a component from one
// frame per position
// with no margin, compared a current position that could be a stale memory, and read sensor
// noise as motion (exact Depth == Depth1, Deg == Deg1). Helper now sends averaged sightings
// taken after the move (currPart: only one cylinder seen; currLost: not seen), and a component
// is named only when the evidence clears a margin; otherwise Faulty asks for more evidence
// (turns to show its flank) or concludes unknown, saying why.

// no_progress: did Faulty move? Planar displacement of the two sightings; a single cylinder
// may stand partialSlack from the centre, so a partial sighting widens the margin.
+!feedback(Init, Curr)[source(R)]
   : reason(no_progress)
   & displacement(Init, Curr, Dist, Slack) & movedLimit(L) & Dist > L + Slack
   <- .print(R, " has reported ", Init, " and then ", Curr, ": moved ", Dist, " m");
      .print("fault in odometry system, thanks ", R);
      -+diagnosis(odometry);                                  // ADDED: outcome belief
      .send(R, achieve, thanks).

+!feedback(Init, Curr)[source(R)]
   : reason(no_progress)
   & displacement(Init, Curr, Dist, 0) & stillLimit(L) & Dist < L
   <- .print(R, " has reported ", Init, " and then ", Curr, ": moved ", Dist, " m");
      .print(" fault in both actuators , thanks ", R);
      -+diagnosis(both_actuators);                            // ADDED: outcome belief
      .send(R, achieve, thanks).

+!feedback(Init, Curr)[source(R)]
   : reason(no_progress)
   <- .print(R, " has reported ", Init, " and then ", Curr);
      !concludeUnknown(R, "cannot tell whether I moved").

// bad_move: which way did Faulty turn? Needs the heading in both sightings.
+!feedback(initPos(D, Dp, Y), currPos(D1, Dp1, Y1))[source(R)]
   : reason(bad_move)
   & turnSeen(initPos(D, Dp, Y), currPos(D1, Dp1, Y1), Turn)
   & turnLimit(L) & turnMargin(M) & Turn > L + M
   <- .print(R, " has reported ", initPos(D, Dp, Y), " and then ", currPos(D1, Dp1, Y1), ": turned ", Turn);
      .print("right actuator has problems , thanks ", R);
      -+diagnosis(right_actuator);                            // ADDED: outcome belief
      .send(R, achieve, thanks).

+!feedback(initPos(D, Dp, Y), currPos(D1, Dp1, Y1))[source(R)]
   : reason(bad_move)
   & turnSeen(initPos(D, Dp, Y), currPos(D1, Dp1, Y1), Turn)
   & turnLimit(L) & turnMargin(M) & Turn < -(L + M)
   <- .print(R, " has reported ", initPos(D, Dp, Y), " and then ", currPos(D1, Dp1, Y1), ": turned ", Turn);
      .print("left actuator has problems , thanks ", R);
      -+diagnosis(left_actuator);                             // ADDED: outcome belief
      .send(R, achieve, thanks).

// FIX(F5): the thesis' false-positive band (|d| < 8, with no plan for exactly 8) is now
// |d| < turnLimit - turnMargin; between the bands the turn is too close to call.
+!feedback(initPos(D, Dp, Y), currPos(D1, Dp1, Y1))[source(R)]
   : reason(bad_move)
   & turnSeen(initPos(D, Dp, Y), currPos(D1, Dp1, Y1), Turn)
   & turnLimit(L) & turnMargin(M) & math.abs(Turn) < L - M
   <- .print(R, " has reported ", initPos(D, Dp, Y), " and then ", currPos(D1, Dp1, Y1), ": turned ", Turn);
      .print("it was a false positive for bad_move, thanks ", R);
      -+diagnosis(false_positive);                            // ADDED: outcome belief
      .send(R, achieve, thanks).

// Too close to call, but seen near the occlusion angle: turn away by a known angle and ask
// for a better view once (FIX(F11)); otherwise unknown.
+!feedback(initPos(D, Dp, Y), currPos(D1, Dp1, Y1))[source(R)]
   : reason(bad_move) & not turnedBy(_)
   & weakView(currPos(D1, Dp1, Y1)) & awayTurn(currPos(D1, Dp1, Y1), T)
   <- .print(R, " sees my heading near the occlusion angle (", currPos(D1, Dp1, Y1), "): turning ", T, " degrees to show my flank");
      +turnedBy(T);
      turn(T);
      !ask(R, achieve, giveFeedback).                         // HOSTS: !ask

+!feedback(initPos(D, Dp, Y), currPos(D1, Dp1, Y1))[source(R)]
   : reason(bad_move)
   & turnSeen(initPos(D, Dp, Y), currPos(D1, Dp1, Y1), Turn)
   <- .print(R, " has reported ", initPos(D, Dp, Y), " and then ", currPos(D1, Dp1, Y1), ": turned ", Turn);
      !concludeUnknown(R, "the turn is too close to the limit").

// The heading is hidden after the move: turn by a known amount to show a flank and ask again;
// the known turn is taken out of the turn Helper then sees (turnSeen).
+!feedback(initPos(D, Dp, Y), Curr)[source(R)]
   : reason(bad_move) & not turnedBy(_) & awayTurn(initPos(D, Dp, Y), T)
   <- .print(R, " cannot see my heading now (", Curr, "): turning ", T, " degrees to show my flank");
      +turnedBy(T);
      turn(T);
      !ask(R, achieve, giveFeedback).                         // HOSTS: !ask

+!feedback(Init, Curr)[source(R)]
   : reason(bad_move)
   <- .print(R, " has reported ", Init, " and then ", Curr);
      !concludeUnknown(R, "my heading could not be seen").

-!feedback(_, _)[source(R)]
   <- !concludeUnknown(R, "I could not turn to show my flank").

+!concludeUnknown(R, Why)
   <- .print("the fault is unknown: ", Why, "; thanks ", R);
      -+diagnosis(unknown);                                   // ADDED: outcome belief
      .send(R, achieve, thanks).
