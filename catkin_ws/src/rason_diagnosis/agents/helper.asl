// Agent helper: thesis (Morais 2015) Appendix A.2, with ONLY the fixes documented in
// docs/thesis-fixes.md of the rason repository. Every change is marked "FIX(Fn):", Fn its entry.
// Added for robots on their own machines (not a thesis fix): handling of a .send to an
// unreachable requester (README, "Link faults"). Marked "HOSTS:".

/* Initial beliefs and rules */
turnRate(5).
centerThreshold(7).
/* Initial goals */
!start.

/* Plans */

+!start : true <- .wait(4000); .print("ZZzzz...").

+!helpme[source(R)]
   <- +helping(R);
      !findRobot(R, 0);
      .print("helper ready.");
      .send(R, tell, found(R)).

// FIX(F6): +!findRobot never gave up; the thesis text says Helper aborts after a full turn
// (360 degrees). It now fails, and -!helpme tells the requester it was not found.
+!findRobot(Robot, Turned)
   : math.abs(Turned) >= 360
   <- .print("Turned ", Turned, " degrees without finding ", Robot, ", giving up");
      .fail(not_found(Robot)).

// HOSTS: R unreachable (see the HOSTS plans below): stop helping it, nothing to tell it.
-!helpme[source(R), error(ia_failed), error_msg(Why)]
   <- .print("cannot reach ", R, ": ", Why);
      -helping(R).
-!helpme[source(R)]                                           // FIX(F6): see above
   <- .print("could not find ", R);
      -helping(R);
      .send(R, tell, notFound(R)).

+!findRobot(Robot, Turned)
   : robot(Robot, Deg, Depth, Yaw)
   & centerThreshold(DT)
   & (math.abs(Deg) >= DT)
   <- .print("Found ", Robot, ", but I need to reposition myself...");
      turn(Deg);
      !findRobot(Robot, Turned + Deg).

+!findRobot(Robot, Turned)
   : robot(Robot, Deg, Depth, Yaw)
   & centerThreshold(DT)
   & math.abs(Deg) < DT
   <- .print("Found ", Robot);
      +foundRobot(Robot, Deg, Depth, Yaw).

+!findRobot(Robot, Turned)
   : turnRate(Rate)
   & centerThreshold(DT)
   <- .print("Finding ", Robot, " turning ", Rate, " degrees, turned ", Turned, " so far. Threshold is ", DT);
      turn(Rate);
      !findRobot(Robot, Turned + Rate).

+!trackMe[source(R)]
   : helping(R)
   & foundRobot(R, Deg, Depth, Yaw)
   <- .print("I'm ready.");
      .send(R, achieve, tryMove).

+!giveFeedback[source(R)]
   : helping(R)
   & foundRobot(R, Deg, Depth, Yaw)
   & robot(R, Deg1, Depth1, Yaw1)
   <- .print("reporting to ", R, " -> ", Deg, " ", Depth, " ", Yaw, " / ", Deg1, " ", Depth1, " ", Yaw1);
      .send(R, achieve, feedback(initPos(Deg, Depth, Yaw), currPos(Deg1, Depth1, Yaw1))).

// HOSTS (robots on their own machines): a .send to R fails with error(ia_failed) and the
// reason in error_msg while R's presence has lapsed (its link is down). Helper stops helping R
// and says why; R ends its diagnosis unknown when no answer comes. (-!helpme: above.)
-!trackMe[source(R), error(ia_failed), error_msg(Why)]
   <- .print("cannot reach ", R, ": ", Why);
      -helping(R);
      -foundRobot(R, _, _, _).
-!giveFeedback[source(R), error(ia_failed), error_msg(Why)]
   <- .print("cannot reach ", R, ": ", Why);
      -helping(R);
      -foundRobot(R, _, _, _).

+!thanks[source(R)]
   : helping(R)
   <- .print(R, " said 'thanks'...");
      .print("You're welcome, ", R);
      -helping(R);
      -foundRobot(R, _, _, _).

// FIX(F7) (reconstruction): the listing is cut at the page end ("<- + robot (...);"). The text
// says this plan "updates the belief about the Faulty". Read literally (+robot), every
// percept leaves a source(self) copy behind, a stale robot(_,Deg,_,_) with |Deg| >= 7 makes
// the repositioning plan above applicable forever and Helper never centres Faulty (the
// thesis found Faulty in every run, so its agent did not do that). -+ keeps one copy: the
// latest; the trigger is restricted to percepts so that the copy does not retrigger it.
+robot(Robot, Deg, Depth, Yaw)[source(percept)]
   <- -+robot(Robot, Deg, Depth, Yaw).
