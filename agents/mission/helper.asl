// Agent helper on a mission (issue 38): the case study's Helper (agents/diagnosis/helper.asl,
// included below), which also takes over a faulty robot's remaining waypoints when offered
// (the contract of agents/mission/faulty.asl: offer -> accept | refuse, then done(I) per
// waypoint and finished, or failed(R)), driving them with its own motion decomposer, around
// the stopped robot (the offer's at(X, Y): where its odometry puts it; navigate.asl's avoid/2).

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

{ include("navigate.asl") }
{ include("../diagnosis/helper.asl") }
