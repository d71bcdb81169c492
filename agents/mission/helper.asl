// Agent helper on a mission (issue 38): the case study's Helper (agents/diagnosis/helper.asl,
// included below), which also takes over a faulty robot's remaining waypoints when offered
// (the contract of agents/mission/faulty.asl: offer -> accept | refuse, then done(I) per
// waypoint and finished, or failed(R)), driving them with its own motion decomposer, around
// the stopped robot (the offer's at(X, Y): where it was last placed; navigate.asl's avoid/2),
// and locates a robot whose odometry is frozen when it asks (whereAmI).

+!offer(Ws, at(FX, FY))[source(F)]
   : not contract(_)
   <- .sort(Ws, Sorted);
      +contract(F);
      -+avoid(FX, FY);
      .print("taking over ", F, "'s waypoints ", Sorted);
      .send(F, tell, accept(Sorted));
      !drive(Sorted, F).
+!offer(_, _)[source(F)] <- .send(F, tell, refuse(busy)).

+!drive([], F)
   <- -contract(F);
      -avoid(_, _);
      .print("all of ", F, "'s waypoints reached");
      .send(F, tell, finished).
+!drive([wp(I, X, Y) | T], F)
   <- .print("driving to ", F, "'s waypoint ", I, " (", X, ", ", Y, ")");
      !goto(X, Y);
      .send(F, tell, done(I));
      !drive(T, F).
-!drive(_, F)[error(R)]
   <- -contract(F);
      -avoid(_, _);
      .print("could not drive ", F, "'s waypoints: ", R);
      .send(F, tell, failed(R)).

// Locating a robot whose odometry is frozen (agents/mission/faulty.asl's guided mode): on
// whereAmI(X, Y) (where that robot expects to be), Helper faces (X, Y), searches and centres it
// (the diagnosis' !locate), averages sightings at rest (!observe) and turns the observation into
// its world pose from Helper's own pose (odometry, healthy): the camera sits cameraAhead of
// Helper's centre; the bearing D (deg, clockwise) and the depth Dp (m, along the optical axis)
// place the centre, and the yaw Y (rason_vision README: Faulty's heading in the camera frame
// plus D) gives its heading. Answer: located(X, Y, Yaw, HX, HY) (HX, HY: where Helper stands),
// with the colour of the one cylinder seen in place of Yaw when only one is, or
// notLocated(not_seen).
cameraAhead(0.135).     // m: the Kinect's optical centre ahead of the base's (turtlebot_sim)
placeOf(D, Dp, X, Y)
   :- pose(HX, HY, HA) & cameraAhead(K) & R = HA * 3.14159265 / 180
    & XR = Dp * math.tan(D * 3.14159265 / 180)
    & X = math.round((HX + (K + Dp) * math.cos(R) + XR * math.sin(R)) * 1000) / 1000
    & Y = math.round((HY + (K + Dp) * math.sin(R) - XR * math.cos(R)) * 1000) / 1000.
worldFix(pos(D, Dp, Yw), X, Y, A) :- placeOf(D, Dp, X, Y) & pose(_, _, HA) & wrap(HA - Yw + D, A).
worldFix(part(D, Dp, C), X, Y, C) :- placeOf(D, Dp, X, Y).

+!whereAmI(X, Y)[source(F)]
   <- +helping(F);                                // its sightings are remembered while searching
      -lastSweep(F, _);
      -fullTurn(F);
      !face(X, Y);                                // where F expects to be after its leg
      !locate(F);
      !observe(F, fix);
      !relook(F);
      ?obs(F, fix, O);
      !answerFix(F, O).
+!answerFix(F, O)
   : worldFix(O, X, Y, A) & pose(HX, HY, _)
   <- -helping(F);
      .abolish(obs(F, fix, _));
      .print("locating ", F, ": ", O, " puts it at (", X, ", ", Y, "), heading ", A);
      .send(F, tell, located(X, Y, A, HX, HY)).
+!answerFix(_, _) <- .fail(error(not_seen)).
// Not seen at all (frames late, Faulty at the view's edge): one more search and look.
+!relook(F) : obs(F, fix, lost) <- !locate(F); !observe(F, fix).
+!relook(_).
// Every failure here is the search's or the observation's: Faulty is told it was not seen.
-!whereAmI(_, _)[source(F), error(R)]
   <- -helping(F);
      .abolish(obs(F, fix, _));
      .print("could not locate ", F, ": ", R);
      .send(F, tell, notLocated(not_seen)).

// Before a diagnosis, face the point where the robot asking says it is (its odometry's pose),
// then let frames of that view come before its helpme starts the search; not while driving a
// contract or helping someone.
lookSettle(1000).       // ms
+!lookAt(X, Y)[source(F)]
   : not contract(_) & not helping(_)
   <- .print("turning to where ", F, " says it is (", X, ", ", Y, ")");
      !face(X, Y);
      .send(F, tell, looking(X, Y)).
+!lookAt(X, Y)[source(F)] <- .send(F, tell, looking(X, Y)).
-!lookAt(X, Y)[source(F)] <- .send(F, tell, looking(X, Y)).
+!face(X, Y) : legTo(X, Y, H, _) & lookSettle(W) <- turn_to(H); .wait(W).
+!face(_, _).

{ include("navigate.asl") }
{ include("../diagnosis/helper.asl") }
