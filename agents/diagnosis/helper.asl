// Agent helper: thesis (Morais 2015) Appendix A.2, with ONLY the fixes documented in
// docs/thesis-fixes.md of the rason repository. Every change is marked "FIX(Fn):", Fn its entry.
// Added for robots on their own machines (not a thesis fix): handling of a .send to an
// unreachable requester (docs/deployment.md, "Link faults"). Marked "HOSTS:".
//
// Percepts (rason_vision's robot synthesizer, conventions in its README):
//   robot(Name, Angle, Depth, Yaw)            both cylinders seen: bearing, depth, yaw
//   robot_partial(Name, Angle, Depth, Colour) one cylinder only: bearing and depth of that
//                                             cylinder, Faulty's heading unknown
//   seen_at(Name, Heading)                    with either: the bearing as a heading of Helper's
//                                             odometry frame at the frame's time (for turn_to)
// A sighting may carry the annotations [moving] (its frame was not taken with Helper's camera at
// rest, or the camera has moved since) and [stamp(Ms)] (its frame's time, ms of ROS time);
//   frame(Ms)                                 with stamps: the time of the newest frame processed,
//                                             with or without a sighting
// Angles in degrees, positive clockwise (to the right); yaw in (-180, 180].

/* Initial beliefs and rules */
centerThreshold(7).     // |bearing| below this: Faulty is centred (thesis)
maxSweeps(3).           // search sweeps (each a full turn cut short by a sighting) before giving up
maxCentring(8).         // centring turns per search before giving up
samples(5).             // full sightings averaged into one observation
sampleTries(16).        // new frames without a usable full sighting before an observation ends
frameWait(4000).        // ms after settleTime that waiting for late frames costs no try
framePeriod(70).        // ms: about one Kinect frame (15 Hz)
settleTime(300).        // ms after an observation starts before its frames may be stamped
sweepBrake(550).        // ms a cut sweep takes to stop: 120 deg/s at the base's 229 deg/s^2
lookStep(45).           // deg between the looks of a careful search (Kinect's view: 57 deg)
lookWait(2000).         // ms a look waits for a frame taken after Helper stopped there
goodRange(1.0, 3.3).    // m: depths where the yaw is reliable and a 0.3 m move stays in view
viewDepth(1.8).         // m: the depth Helper moves to when Faulty is outside goodRange
occlusionMargin(20).    // deg: relative headings this close to +90 (orange hides green) are weak
flankTurn(60).          // deg: how far Faulty is asked to turn to show its flank

// FIX(F8): every angle difference is wrapped into (-180, 180] (the thesis' arithmetic read a
// turn across +-180 as a turn of ~340 degrees the other way).
wrap(A, W) :- W = A - 360 * math.ceil((A - 180) / 360).

// Faulty in view (a full or a partial sighting, only a current percept: never a memory).
sees(R, Deg, Depth) :- robot(R, Deg, Depth, _)[source(percept)].
sees(R, Deg, Depth) :- robot_partial(R, Deg, Depth, _)[source(percept)].

// FIX(F10): a sighting an observation may use: from a frame taken with Helper's camera at rest
// (not [moving]) and, when frames are stamped, stamped after After (ms of ROS time: the
// observation's start plus settleTime, then the last frame used, so no frame counts twice).
// Without stamps (a synthesizer without ~frame_stamps) any current percept at rest counts.
// newFrame: a frame processed since After (a try when it brings no usable full sighting).
usable(R, D, Dp, Y, After, T)
   :- robot(R, D, Dp, Y)[source(percept), stamp(T)] & T > After & not robot(R, D, Dp, Y)[moving].
usable(R, D, Dp, Y, After, After)
   :- robot(R, D, Dp, Y)[source(percept)] & not robot(R, D, Dp, Y)[stamp(_)]
    & not robot(R, D, Dp, Y)[moving].
newFrame(After, T) :- frame(T)[source(percept)] & T > After.
usablePart(R, D, Dp, C, After)
   :- robot_partial(R, D, Dp, C)[source(percept), stamp(T)] & T > After
    & not robot_partial(R, D, Dp, C)[moving].
usablePart(R, D, Dp, C, _)
   :- robot_partial(R, D, Dp, C)[source(percept)] & not robot_partial(R, D, Dp, C)[stamp(_)]
    & not robot_partial(R, D, Dp, C)[moving].

// Where Faulty was last seen, as a heading of Helper's odometry frame: the current percept's, else
// the last one remembered during this search (Faulty may have left the view while Helper braked).
sightedAt(R, H) :- seen_at(R, H)[source(percept)].
sightedAt(R, H) :- not seen_at(R, _)[source(percept)] & sighting(R, H).

// Faulty is in view now, or was sighted during this search: a careful search stops looking.
inView(R) :- sightedAt(R, _) | sees(R, _, _).

// Centred (the thesis: |bearing| < centerThreshold). Once Helper has turned to a heading, the
// bearing is read in its odometry frame, where a frame taken while turning (or late) is as good
// as one taken at rest; before that (Helper at rest, not swept), on the percept as the thesis.
centred(R)
   :- facing(R, F) & sightedAt(R, H) & wrap(H - F, E) & centerThreshold(DT) & math.abs(E) < DT.
centred(R)
   :- not facing(R, _) & not swept(R) & sees(R, Deg, _) & centerThreshold(DT) & math.abs(Deg) < DT.

// Search direction: back against the last sweep when a sighting was lost by overshooting it;
// otherwise clockwise, as the thesis' Helper.
searchSide(R, Dir) :- lastSweep(R, D) & Dir = -D.
searchSide(_, 1) :- true.

// Mean of full sightings s(Deg, Depth, Yaw); the yaw is averaged as wrapped offsets from the
// first sample, so samples on both sides of +-180 average correctly.
sumObs([], _, 0, 0, 0) :- true.
sumObs([s(D, Dp, Y) | T], Y0, SD, SDp, SW)
   :- sumObs(T, Y0, SD1, SDp1, SW1) & wrap(Y - Y0, W)
    & SD = SD1 + D & SDp = SDp1 + Dp & SW = SW1 + W.
meanObs([s(D, Dp, Y) | T], pos(MD, MDp, MY))
   :- sumObs([s(D, Dp, Y) | T], Y, SD, SDp, SW) & .length([s(D, Dp, Y) | T], N)
    & wrap(Y + SW / N, WY)
    & MD = math.round(SD / N * 10) / 10 & MDp = math.round(SDp / N * 1000) / 1000
    & MY = math.round(WY * 10) / 10.

// Faulty's heading relative to the line of sight: Yaw = heading + Angle (rason_vision README),
// so heading - Angle = Yaw - 2 Angle. Near +90 its right (orange, tall) cylinder hides the
// left (green) one: the yaw is unreliable there, or no full sighting at all.
nearOcclusion(pos(D, _, Y), T)
   :- wrap(Y - 2 * D - 90, E) & occlusionMargin(M) & math.abs(E) < M & flankTurn(F)
    & ((E >= 0 & T = F) | (E < 0 & T = -F)).
nearOcclusion(part(_, _, _), T) :- flankTurn(T).

// The feedback's terms: initPos/currPos as in the thesis for full sightings. (Facts with
// variables are written as rules so that each use gets fresh variables.)
initTerm(pos(D, Dp, Y), initPos(D, Dp, Y)) :- true.
initTerm(part(D, Dp, C), initPart(D, Dp, C)) :- true.
currTerm(pos(D, Dp, Y), currPos(D, Dp, Y)) :- true.
currTerm(part(D, Dp, C), currPart(D, Dp, C)) :- true.
currTerm(lost, currLost) :- true.

/* Initial goals */
!start.

/* Plans */

+!start : true <- .wait(4000); .print("ZZzzz...").

// FIX(F9): the thesis searched in 5-degree steps, always clockwise (9-13 s of every run, the long
// way round when Faulty was on the left). Helper now sweeps a full turn in one action (120 deg/s)
// and cuts it short at the first sighting; once the base has braked it turns to the heading of
// its odometry frame where it saw Faulty (seen_at, turn_to: right however late the percept came,
// and though braking took Faulty out of view again), and the thesis' centring (7 degrees) is
// read in that frame. Budget and alternatives: docs/thesis-fixes.md, F9.
+!helpme[source(R)]
   <- +helping(R);
      -lastSweep(R, _);
      -fullTurn(R);
      -flankAsked(R);
      -relooked(R);
      !locate(R);
      .print("helper ready.");
      .send(R, tell, found(R)).

// FIX(F6): +!findRobot never gave up; the thesis text says Helper aborts after a full turn
// (360 degrees). It now fails, and -!helpme tells the requester it was not found.
// HOSTS: R unreachable (see the HOSTS plans below): stop helping it, nothing to tell it.
-!helpme[source(R), error(ia_failed), error_msg(Why)]
   <- .print("cannot reach ", R, ": ", Why);
      -helping(R);
      -sweeping(R).
-!helpme[source(R)]
   <- .print("could not find ", R);
      -helping(R);
      -sweeping(R);
      .send(R, tell, notFound(R)).

// A search from here: nothing remembered of an earlier one (Helper or Faulty may have moved).
+!locate(Robot)
   <- -facing(Robot, _);
      -sighting(Robot, _);
      -swept(Robot);
      -lookedAround(Robot);
      !findRobot(Robot, 0, 0).

+!findRobot(Robot, _, _)
   : centred(Robot)
   <- .print("Found ", Robot).

+!findRobot(Robot, _, Steps)
   : maxCentring(M)
   & Steps >= M
   <- .print("Could not centre ", Robot, " in ", Steps, " turns, giving up");
      .fail(not_centred(Robot)).

// Centring on the heading where Faulty was seen (turn_to: the motion decomposer turns the short
// way to that heading of the odometry frame, however far Helper braked past it).
+!findRobot(Robot, Sweeps, Steps)
   : sightedAt(Robot, H)
   <- .print("Found ", Robot, ", but I need to reposition myself...");
      turn_to(H);
      -+facing(Robot, H);
      !findRobot(Robot, Sweeps, Steps + 1).

// Without seen_at (a synthesizer without ~odom_bearings): the thesis' turn by the bearing.
+!findRobot(Robot, Sweeps, Steps)
   : sees(Robot, Deg, _)
   <- .print("Found ", Robot, ", but I need to reposition myself...");
      -swept(Robot);
      turn(Deg);
      !findRobot(Robot, Sweeps, Steps + 1).

// FIX(F9), the careful search: a sweep outruns a camera whose frames come too seldom (a loaded
// machine drops frames: at 3 frames/s, 120 deg/s turns 40 deg between frames, and Faulty may fall
// between them). So a full turn without a sighting is followed by a search that does not depend
// on the frame rate: a look from every lookStep of the circle, each waiting for a frame taken
// there at rest. Only a circle of looks without a sighting gives up (F6).
+!findRobot(Robot, Sweeps, Steps)
   : fullTurn(Robot) & not lookedAround(Robot) & lookStep(D)
   <- -fullTurn(Robot);
      +lookedAround(Robot);
      .print("Nothing seen while sweeping: looking around ", Robot, " every ", D, " degrees");
      !lookAround(Robot, math.ceil(360 / D));
      !findRobot(Robot, Sweeps, Steps).

+!findRobot(Robot, _, _)
   : fullTurn(Robot)
   <- -fullTurn(Robot);
      .print("Turned 360 degrees without finding ", Robot, ", giving up");
      .fail(not_found(Robot)).

+!findRobot(Robot, Sweeps, _)
   : maxSweeps(M)
   & Sweeps >= M
   <- .print("Lost ", Robot, " ", Sweeps, " times while searching, giving up");
      .fail(not_found(Robot)).

+!findRobot(Robot, Sweeps, Steps)
   : searchSide(Robot, Dir) & sweepBrake(S)
   <- .print("Searching ", Robot, ": sweeping ", Dir * 360, " degrees");
      !sweep(Robot, Dir);
      +swept(Robot);
      .wait(S);       // cut at a sighting: let the base stop, then turn to where Faulty was
      !findRobot(Robot, Sweeps + 1, Steps).   // seen (a turn from rest ends where it should)

+!sweep(Robot, Dir)
   <- -+lastSweep(Robot, Dir);
      +sweeping(Robot);
      turn(Dir * 360);
      -sweeping(Robot);
      +fullTurn(Robot).

-!sweep(Robot, _) <- -sweeping(Robot).

// A careful search with Looks looks left: Faulty in view, the search goes on from here
// (findRobot); else a look here, then a step on to the next, unless this was the last look.
+!lookAround(Robot, _)
   : inView(Robot).
+!lookAround(Robot, Looks)
   : searchSide(Robot, Dir) & lookStep(D) & settleTime(S) & lookWait(W)
   <- .time(Now);
      .wait(S);
      !awaitFrame(Now + S, W);
      !stepOn(Robot, Dir * D, Looks).

+!stepOn(Robot, _, _)
   : inView(Robot).
+!stepOn(Robot, _, 1)
   <- +fullTurn(Robot).
+!stepOn(Robot, Turn, Looks)
   <- turn(Turn);
      !lookAround(Robot, Looks - 1).

// Frames are stamped (the synthesizer's ~frame_stamps): remembered, as the percepts of a camera
// silent for longer than their time to live are cleared, frame(Ms) with them.
+frame(_)[source(percept)] : not stampedFrames <- +stampedFrames.

// A frame taken after After (ms of ROS time) has been processed, or Left ms have passed. Without
// frame stamps (a synthesizer without ~frame_stamps) the percepts are the newest frame's: after
// settleTime at rest they show this heading.
+!awaitFrame(After, _)
   : newFrame(After, _) | not stampedFrames.
+!awaitFrame(_, Left)
   : Left <= 0 & lookWait(W)
   <- .print("No new camera frame in ", W, " ms: looking on").
+!awaitFrame(After, Left)
   : framePeriod(P)
   <- .wait(P);
      !awaitFrame(After, Left - P).

// Every sighting's heading is remembered during a search (sightedAt).
+seen_at(Robot, H)[source(percept)]
   : helping(Robot)
   <- -+sighting(Robot, H).

// A sighting during a sweep ends it: the dropped turn is cancelled at the motion decomposer,
// which stops the base at once; the search goes on from where it comes to rest.
+robot(Robot, _, _, _)[source(percept)]
   : sweeping(Robot)
   <- -sweeping(Robot);
      .succeed_goal(sweep(Robot, _)).

+robot_partial(Robot, _, _, _)[source(percept)]
   : sweeping(Robot)
   <- -sweeping(Robot);
      .succeed_goal(sweep(Robot, _)).

// FIX(F7) (reconstruction): the thesis' last plan (cut at the page end) copied every robot(...)
// percept into a source(self) belief; that copy outlived the sighting and was reported as
// Faulty's current position after Faulty had left the view. Helper now only reasons on current
// percepts (sees/3, observations below) and has no such copy.

// ---- evidence ------------------------------------------------------------------------------
// FIX(F10): the thesis compared two single frames, the second possibly older than the end of the
// move. An observation averages `samples` full sightings from frames taken with Helper's camera
// at rest and stamped at least settleTime after the observation started (after Helper's own
// motion ended and after Faulty's request, which Faulty sends once its move has ended), however
// late those frames reach Helper: obs(R, Label, pos(Deg, Depth, Yaw)); with too few full
// sightings it is part(Deg, Depth, Colour) (one cylinder seen: yaw unknown) or lost. It ends
// after `sampleTries` new frames without a usable full sighting; until frameWait has passed, a
// poll that brings no new frame at all (frames late, or a gap) costs no try, so late frames do
// not shorten the observation. Each frame is used once (After: the newest frame used).
+!observe(R, Label)
   : settleTime(S) & sampleTries(M) & frameWait(W)
   <- -obs(R, Label, _);
      .time(Now);
      .wait(S);
      !collect(R, Label, Now + S, Now + S + W, M, [], []).

+!collect(R, Label, _, _, _, Full, _)
   : samples(K) & .length(Full, N) & N >= K & meanObs(Full, Obs)
   <- +obs(R, Label, Obs).

+!collect(R, Label, _, _, 0, Full, _)
   : .length(Full, N) & N >= 3 & meanObs(Full, Obs)
   <- +obs(R, Label, Obs).

+!collect(R, Label, _, _, 0, _, [p(D, Dp, C) | _])
   <- +obs(R, Label, part(D, Dp, C)).

+!collect(R, Label, _, _, 0, _, _)
   <- +obs(R, Label, lost).

// a usable full sighting: a sample
+!collect(R, Label, After, Until, Tries, Full, Part)
   : usable(R, D, Dp, Y, After, T) & framePeriod(P)
   <- .wait(P);
      !collect(R, Label, T, Until, Tries, [s(D, Dp, Y) | Full], Part).

// a new frame without one: a try (a partial sighting in it is kept)
+!collect(R, Label, After, Until, Tries, Full, Part)
   : newFrame(After, T) & usablePart(R, D, Dp, C, After) & framePeriod(P)
   <- .wait(P);
      !collect(R, Label, T, Until, Tries - 1, Full, [p(D, Dp, C) | Part]).

+!collect(R, Label, After, Until, Tries, Full, Part)
   : newFrame(After, T) & framePeriod(P)
   <- .wait(P);
      !collect(R, Label, T, Until, Tries - 1, Full, Part).

// no new frame: free while frames may still be on their way (until Until), then a try
+!collect(R, Label, After, Until, Tries, Full, Part)
   : framePeriod(P) & .time(Now) & Now < Until
   <- .wait(P);
      !collect(R, Label, After, Until, Tries, Full, Part).

+!collect(R, Label, After, Until, Tries, Full, Part)
   : usablePart(R, D, Dp, C, After) & framePeriod(P)
   <- .wait(P);
      !collect(R, Label, After, Until, Tries - 1, Full, [p(D, Dp, C) | Part]).

+!collect(R, Label, After, Until, Tries, Full, Part)
   : framePeriod(P)
   <- .wait(P);
      !collect(R, Label, After, Until, Tries - 1, Full, Part).

// FIX(F12) (future work of the thesis: repositioning the observer): beyond goodRange the yaw is
// noisy (far) or Faulty's test move may leave the view (near); Helper drives along its line of
// sight to viewDepth and centres Faulty again.
+!viewpoint(R)
   : sees(R, _, Depth) & goodRange(Lo, Hi) & (Depth < Lo | Depth > Hi) & viewDepth(V)
   <- Dist = math.round((Depth - V) * 100) / 100;
      .print(R, " is ", Depth, " m away: moving ", Dist, " m for a better view");
      move(Dist);
      !locate(R).
+!viewpoint(_).

+!trackMe[source(R)]
   : helping(R)
   <- !viewpoint(R);
      !observe(R, init);
      !ready(R).

// FIX(F11) (future work of the thesis: against self-occlusion): when only one cylinder is seen,
// or Faulty's heading is near the occlusion angle, Faulty is asked once to turn and show its
// flank; it answers with trackMe again and the initial observation is taken anew.
+!ready(R)
   : obs(R, init, O) & nearOcclusion(O, T) & not flankAsked(R)
   <- +flankAsked(R);
      .print("I cannot see ", R, "'s heading well (", O, "): asking it to turn ", T, " degrees");
      .send(R, achieve, showFlank(T)).

+!ready(R)
   : obs(R, init, lost) & not relooked(R)
   <- +relooked(R);
      .print("I lost sight of ", R, ", looking again");
      !locate(R);
      !observe(R, init);
      !ready(R).

+!ready(R)
   : obs(R, init, lost)
   <- .fail(lost_sight(R)).

+!ready(R)
   : obs(R, init, O)
   <- .print("I'm ready: ", R, " is at ", O);
      .send(R, achieve, tryMove).

// HOSTS (robots on their own machines): a .send to R fails with error(ia_failed) and the
// reason in error_msg while R's presence has lapsed (its link is down). Helper stops helping R
// and says why; R ends its diagnosis unknown when no answer comes. (-!helpme: above.)
-!trackMe[source(R), error(ia_failed), error_msg(Why)] <- !unreachable(R, Why).
-!giveFeedback[source(R), error(ia_failed), error_msg(Why)] <- !unreachable(R, Why).
-!ready(R)[error(ia_failed), error_msg(Why)] <- !unreachable(R, Why).
+!unreachable(R, Why)
   <- .print("cannot reach ", R, ": ", Why);
      -helping(R);
      .abolish(obs(R, _, _)).   // both of them: init and curr

-!trackMe[source(R)]
   <- .print("could not track ", R);
      -helping(R);
      .send(R, tell, notFound(R)).

-!ready(R)
   <- .print("could not track ", R);
      -helping(R);
      .send(R, tell, notFound(R)).

// FIX(F10): the thesis reported the position it last kept (possibly from before the move, or from
// before Faulty turned out of sight) as the current one. The current position now comes from
// an observation taken after the move has ended; if it is only partial or lost, the feedback
// says so (currPart / currLost) instead of reporting a stale position.
+!giveFeedback[source(R)]
   : helping(R)
   <- !observe(R, curr);
      !recheck(R);
      ?obs(R, init, I);
      ?obs(R, curr, C);
      ?initTerm(I, Init);
      ?currTerm(C, Curr);
      .print("reporting to ", R, " -> ", Init, " / ", Curr);
      .send(R, achieve, feedback(Init, Curr)).


// A current observation with too few sightings gets one more look from the same viewpoint
// (Helper does not turn: the two positions must share its camera's frame). Frames can come
// late while the machine is busy, and a percept that outlived its time to live is cleared;
// only a second miss is reported as currLost / currPart.
+!recheck(R)
   : obs(R, curr, C) & (C = lost | C = part(_, _, _))
   <- .print("too few sightings of ", R, " after its move (", C, "), looking again");
      !observe(R, curr).
+!recheck(_).

+!thanks[source(R)]
   : helping(R)
   <- .print(R, " said 'thanks'...");
      .print("You're welcome, ", R);
      -helping(R);
      -flankAsked(R);
      .abolish(obs(R, _, _)).   // both of them: init and curr
