"""The case study's two agents (agents/diagnosis/faulty.asl and helper.asl) against a scripted world.

A fake environment plays both robots and Helper's camera: Faulty's move/turn actions succeed
or fail per scenario, Helper's ``robot(faulty,Deg,Depth,Yaw)`` percepts follow the scripted
geometry, and a virtual clock makes ``.wait(4000)`` instant.
"""

from __future__ import annotations

import io
import math
import os

import pytest

from rason.asl import LocalArch, LocalMas, VirtualClock, load_mas2j, parse_literal
from rason.asl.inspection import mind_text
from rason.asl.terms import Literal

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
AGENTS = os.path.join(ROOT, "agents", "diagnosis")
FOV_HALF = 28.5  # Kinect: 57 degrees horizontal
TURN_STEP = 2.0   # degrees Helper turns per reasoning cycle while a turn action runs
OCCLUDED = 5.0    # relative headings within this of +90: the orange cylinder hides the green


def wrap(a: float) -> float:
    """Degrees into (-180, 180]."""
    a = math.fmod(a, 360.0)
    return a + 360.0 if a <= -180.0 else a - 360.0 if a > 180.0 else a


class World:
    """Scripted planar geometry, angles in degrees clockwise (as Helper's camera sees them).

    Helper stands at the origin with heading ``heading``; Faulty at ``bearing`` (absolute) and
    ``distance`` with its own absolute ``faulty_heading``. Faulty's test move curves by
    ``curve`` degrees per move (right = +) and advances ``advance`` metres.
    """

    def __init__(self, scenario: str, bearing: float = 90.0, distance: float = 1.5,
                 relative_heading: float = -90.0, curve: float | None = None,
                 visible: bool = True, advance: float = 0.15) -> None:
        self.scenario = scenario
        self.heading = 0.0
        self.x = distance * math.sin(math.radians(bearing))   # right
        self.y = distance * math.cos(math.radians(bearing))   # forward
        self.faulty_heading = wrap(bearing + relative_heading)
        self.moves = 0
        self.visible = visible and scenario != "unknown"
        default_curve = {"right_actuator": 20.0, "left_actuator": -20.0, "exact8": 8.0,
                         "exact_minus8": -8.0}
        self.curve = curve if curve is not None else default_curve.get(scenario, 0.0)
        self.advance = advance
        self.vanish_on_move: int | None = None  # Faulty leaves the view on this move
        self.occlusion_bias = 0.0   # deg the yaw is pushed away from the occlusion angle near it
        self.helper_turns: list[float] = []
        self.faulty_turns: list[float] = []
        self.odom_bearings = False  # the synthesizer adds seen_at(faulty, Heading)
        self.brake = 0.0   # deg Helper coasts on after a turn is given up (braking, latency)
        # Frames too seldom for Helper's search sweep (a loaded machine): no frame taken during a
        # full turn shows Faulty, while frames taken during shorter turns or at rest do.
        self.blind_sweep = False
        self.sweeping = False   # a turn of 360 degrees or more is running
        # Helper's link to Faulty goes down when Helper first sends a message of this functor
        # (its .send then fails, as it does on a real network while Faulty's presence lapsed)
        self.cut_on: str | None = None
        self.cut = False
        self.beliefs: dict[str, list[str]] = {}   # each agent's, when the run ended
        # The synthesizer's ~frame_stamps and [moving] (issue 15, F10): every Helper turn step
        # takes `step_s` of the clock; Helper's camera frames are taken every reasoning cycle,
        # annotated [stamp(Ms)] and, when Helper turned or drove between the frame and its
        # delivery, [moving]; each reaches Helper `latency_ms` after it was taken, with
        # frame(Ms) whether Faulty is in it or not.
        self.stamps = False
        self.step_s = 0.0
        self.latency_ms = 0.0
        self.helper_moves = 0       # Helper's drives so far (a frame before one is [moving])
        self.frames: list[tuple[float, float, int, list[str]]] = []  # (ms, heading, moves, texts)

    # -- geometry -------------------------------------------------------------------------
    @property
    def bearing(self) -> float:
        return math.degrees(math.atan2(self.x, self.y))

    @property
    def distance(self) -> float:
        return math.hypot(self.x, self.y)

    def percepts(self) -> list:
        return [parse_literal(text) for text in self.percept_texts()]

    def camera(self, now_ms: float) -> list:
        """What Helper perceives at `now_ms` with stamped frames: the newest frame taken at
        least `latency_ms` before, [moving] when Helper's camera moved since it was taken."""
        self.frames.append((now_ms, self.heading, self.helper_moves, self.percept_texts()))
        late = [f for f in self.frames if f[0] <= now_ms - self.latency_ms]
        if not late:
            return []
        taken, heading, moves, texts = late[-1]
        moving = abs(wrap(self.heading - heading)) > 0.3 or moves != self.helper_moves
        annots = f"[{'moving,' if moving else ''}stamp({taken:.0f})]"
        return [*(parse_literal(t + annots if t.startswith("robot") else t) for t in texts),
                parse_literal(f"frame({taken:.0f})")]

    def percept_texts(self) -> list[str]:
        rel = wrap(self.bearing - self.heading)
        if not self.visible or abs(rel) > FOV_HALF or not 0.5 < self.distance < 4.5:
            return []
        if self.blind_sweep and self.sweeping:
            return []
        depth = round(self.distance * math.cos(math.radians(rel)), 3)
        facing = wrap(self.faulty_heading - self.heading)          # heading in the camera
        relative = wrap(self.faulty_heading - self.bearing)        # heading - line of sight
        # Helper's odometry frame is the world's here: the heading of the sighting
        seen = [f"seen_at(faulty,{wrap(self.heading + rel):.1f})"] if self.odom_bearings else []
        if abs(wrap(relative - 90.0)) < OCCLUDED:
            return [f"robot_partial(faulty,{rel:.2f},{depth},orange)", *seen]
        off = wrap(relative - 90.0)
        if abs(off) < 15.0:       # as the real detector: near occlusion the yaw is pushed away
            facing += math.copysign(self.occlusion_bias, off)
        yaw = wrap(facing + rel)
        return [f"robot(faulty,{rel:.2f},{depth},{yaw:.2f})", *seen]

    def _advance(self, dist: float, turn: float) -> None:
        """Faulty drives ``dist`` m while turning ``turn`` degrees (the chord of the arc)."""
        mid = math.radians(self.faulty_heading + turn / 2.0)
        self.x += dist * math.sin(mid)
        self.y += dist * math.cos(mid)
        self.faulty_heading = wrap(self.faulty_heading + turn)

    # -- Faulty's actions -----------------------------------------------------------------
    def move(self, dist: float) -> tuple[bool, str | None]:
        """Faulty's move: (ok, failure reason)."""
        self.moves += 1
        if self.moves == self.vanish_on_move:
            self.visible = False
        s = self.scenario
        if s == "no_fault":
            return True, None
        if s in ("both_actuators", "unknown"):
            return False, "no_progress"
        if s == "odometry":
            self._advance(self.advance * (1 if dist > 0 else -1), 0.0)
            return False, "no_progress"
        if s in ("right_actuator", "left_actuator", "exact8", "exact_minus8"):
            self._advance(0.1 * (1 if dist > 0 else -1), self.curve)
            return False, "bad_move"
        if s == "false_positive":
            # the first two attempts (goToDestination, then its retry) fail; tryMove works
            return (self.moves > 2), (None if self.moves > 2 else "bad_move")
        raise AssertionError(s)

    def faulty_turn(self, degrees: float) -> tuple[bool, str | None]:
        self.faulty_turns.append(degrees)
        if self.scenario == "both_actuators":
            return False, "no_progress"
        self.faulty_heading = wrap(self.faulty_heading + degrees)
        return True, None

    def helper_move(self, dist: float) -> None:
        """Helper drives along its heading: Faulty's relative position shifts back."""
        h = math.radians(self.heading)
        self.helper_moves += 1
        self.x -= dist * math.sin(h)
        self.y -= dist * math.cos(h)


class RobotArch(LocalArch):
    """Architecture of one robot in the scripted world.

    Faulty's actions and Helper's moves complete a few reasoning cycles after they start;
    Helper's turns run TURN_STEP degrees per tick, and a new action preempts a running one
    (as the motion decomposer does), so a sighting can cut a search sweep short.
    """

    ACTION_CYCLES = 3  # an action completes a few reasoning cycles after it started

    def __init__(self, mas: LocalMas, name: str, world: World) -> None:
        super().__init__(mas, mas.clock)
        self.name = name
        self.world = world
        self._last: list | None = None
        self._running: list = []  # [cycles left, agent, action_id, ok, reason, turn left]

    def _tick(self) -> None:
        for entry in list(self._running):
            if entry[5]:
                step = math.copysign(min(TURN_STEP, abs(entry[5])), entry[5])
                self.world.heading = wrap(self.world.heading + step)
                entry[5] -= step
                if self.world.step_s:
                    self.clock.advance(self.world.step_s)
                if abs(entry[5]) > 1e-9:
                    continue
                self.world.sweeping = False
            entry[0] -= 1
            if entry[0] <= 0:
                self._running.remove(entry)
                _, agent, aid, ok, reason, _ = entry
                agent.action_feedback(aid, ok, reason, "" if ok else f"{reason} while moving")

    def perceive(self):
        self._tick()
        if self.name != "helper":
            return None
        w = self.world
        p = w.camera(self.clock.now() * 1000.0) if w.stamps else w.percepts()
        if p == self._last:
            return None
        self._last = p
        return p

    def send(self, agent, message) -> None:
        w = self.world
        if self.name == "helper" and (w.cut or getattr(message.content, "functor", None) == w.cut_on):
            w.cut = True
            raise ConnectionError(f"{message.receiver} not heard for 3.5 s")
        super().send(agent, message)

    def action_abandoned(self, agent, action_id: int) -> None:
        """The agent gave the action up (e.g. a sweep ended by a sighting): stop it, as the
        motion decomposer does on jason/cancel; the base coasts ``world.brake`` degrees on)."""
        for entry in [e for e in self._running if e[2] == action_id]:
            if entry[5]:
                coast = math.copysign(min(self.world.brake, abs(entry[5])), entry[5])
                self.world.heading = wrap(self.world.heading + coast)
                self.world.sweeping = False
        self._running = [e for e in self._running if e[2] != action_id]

    def act(self, agent, action: Literal, action_id: int) -> None:
        w = self.world
        turn = 0.0
        for entry in list(self._running):   # a new action preempts the running one
            self._running.remove(entry)
            entry[1].action_feedback(entry[2], False, "preempted", "preempted")
        value = float(action.args[0])
        if action.functor == "move" and self.name == "faulty":
            ok, reason = w.move(value)
        elif action.functor == "turn" and self.name == "faulty":
            ok, reason = w.faulty_turn(value)
        elif action.functor == "turn" and self.name == "helper":
            w.helper_turns.append(value)
            w.sweeping = abs(value) >= 360.0
            ok, reason, turn = True, None, value
        elif action.functor == "turn_to" and self.name == "helper":   # the short way
            turn = wrap(value - w.heading)
            w.helper_turns.append(turn)
            ok, reason = True, None
        elif action.functor == "move" and self.name == "helper":
            w.helper_move(value)
            ok, reason = True, None
        else:
            ok, reason = False, "unknown_action"
        self._running.append([self.ACTION_CYCLES, agent, action_id, ok, reason, turn])


def run_scenario(scenario: str, **layout) -> tuple[list[str], str]:
    return run_world(World(scenario, **layout))


def run_world(world: World) -> tuple[list[str], str]:
    """Run both agents in `world`: Faulty's beliefs at the end, and the console."""
    out = io.StringIO()
    mas = LocalMas(clock=VirtualClock(), out=out,
                   arch_factory=lambda m, name: RobotArch(m, name, world))
    mas.load_project(load_mas2j(os.path.join(AGENTS, "diagnosis.mas2j")))
    archs = [ag.arch for ag in mas.agents.values()]

    def finish_actions() -> bool:
        busy = [a for a in archs if a._running]
        for a in busy:
            a._tick()
        return bool(busy)
    assert mas.run(timeout=3600, max_cycles=200000, idle_hook=finish_actions), "agents did not settle"
    world.beliefs = {name: [str(b) for b in mind_text(ag)["beliefs"]] for name, ag in mas.agents.items()}
    return [str(b) for b in mind_text(mas.agents["faulty"])["beliefs"]], out.getvalue()


def diagnoses(beliefs: list[str]) -> list[str]:
    return [b for b in beliefs if b.startswith("diagnosis(")]


@pytest.mark.parametrize("scenario,expected", [
    ("no_fault", "no_fault"),
    ("both_actuators", "both_actuators"),
    ("odometry", "odometry"),
    ("right_actuator", "right_actuator"),
    ("left_actuator", "left_actuator"),
    ("false_positive", "false_positive"),
    ("exact8", "unknown"),          # a turn at the thesis' limit: too close to call
    ("exact_minus8", "unknown"),
    ("unknown", "unknown"),
])
def test_diagnosis(scenario: str, expected: str) -> None:
    beliefs, out = run_scenario(scenario)
    assert diagnoses(beliefs) == [f"diagnosis({expected})[source(self)]"], out
    assert "No failure event" not in out, out


def test_helper_forgets_faulty_once_thanked() -> None:
    world = World("odometry")
    beliefs, out = run_world(world)
    assert diagnoses(beliefs) == ["diagnosis(odometry)[source(self)]"], out
    assert "[helper] You're welcome, faulty" in out
    kept = [b for b in world.beliefs["helper"] if b.startswith(("helping(faulty", "obs(faulty"))]
    assert not kept, kept


def test_console_story_both_actuators() -> None:
    _, out = run_scenario("both_actuators")
    for text in ["[faulty] Moving to Destination", "[faulty] something went wrong...no_progress",
                 "[faulty] Cannot solve problem alone, asking for help.", "[helper] Found faulty",
                 "[faulty] helper found me, asking to track me", "[helper] I'm ready: faulty is at pos(",
                 "[faulty]  requesting some feedback from helper",
                 "[faulty]  fault in both actuators , thanks helper", "[helper] You're welcome, helper"
                 if False else "[helper] You're welcome, faulty"]:
        assert text in out, out


@pytest.mark.parametrize("cut_on", ["tryMove", "feedback"])
def test_helper_stops_helping_a_robot_it_cannot_reach(cut_on: str) -> None:
    # the link goes down as Helper tells Faulty to move (-!ready) or sends it what it saw
    # (-!giveFeedback): Helper says why and forgets Faulty; Faulty names no component
    world = World("right_actuator")
    world.cut_on = cut_on
    beliefs, out = run_world(world)
    assert world.cut
    assert "[helper] cannot reach faulty: cannot send to faulty: faulty not heard for 3.5 s" in out, out
    helper = world.beliefs["helper"]
    assert not [b for b in helper if b.startswith(("helping(faulty", "obs(faulty"))], helper
    assert diagnoses(beliefs) in ([], ["diagnosis(unknown)[source(self)]"]), (beliefs, out)


def test_helper_gives_up_after_full_turn() -> None:
    beliefs, out = run_scenario("unknown")
    assert "[helper] Turned 360 degrees without finding faulty, giving up" in out
    assert "[faulty] helper could not find me: the fault is unknown" in out
    assert 'unknownBecause("the helper could not find me or keep me in view")[source(self)]' \
        in beliefs, beliefs


# -- layouts other than the thesis' (issue 15) ---------------------------------------------------
# The first two moves (goToDestination and its retry) curve too, so a layout is given by where
# Faulty's heading is at the test move: start = test heading - 2 * curve.

def diagnosis_of(world: World) -> tuple[str, str]:
    beliefs, out = run_world(world)
    diags = diagnoses(beliefs)
    assert len(diags) == 1, out
    return diags[0].split("(")[1].split(")")[0], out


@pytest.mark.parametrize("scenario,curve", [("right_actuator", 20.0), ("left_actuator", -20.0)])
def test_turn_across_180_is_wrapped(scenario, curve):
    """Faulty facing Helper's camera: its yaw crosses +-180 during the test move."""
    test_heading = 170.0 if curve > 0 else -170.0        # ends at -170 / +170
    world = World(scenario, bearing=30.0, distance=1.5, relative_heading=test_heading - 2 * curve,
                  curve=curve)
    diagnosis, out = diagnosis_of(world)
    assert diagnosis == scenario, out


@pytest.mark.parametrize("scenario", ["right_actuator", "left_actuator", "both_actuators",
                                      "odometry"])
def test_self_occlusion_at_the_start_is_cleared(scenario):
    """One cylinder hides the other when Helper first looks: Faulty is asked to show its flank
    (both_actuators cannot turn: its diagnosis needs no heading) and the result is right."""
    curve = {"right_actuator": 20.0, "left_actuator": -20.0}.get(scenario, 0.0)
    world = World(scenario, bearing=60.0, relative_heading=90.0 - 2 * curve, curve=curve)
    diagnosis, out = diagnosis_of(world)
    assert "robot_partial" not in out  # (percepts are not printed; the agents speak of part)
    assert "asking it to turn" in out, out
    assert world.faulty_turns, out
    assert diagnosis == scenario, out


@pytest.mark.parametrize("scenario,curve", [("right_actuator", 25.0), ("left_actuator", -25.0)])
def test_heading_hidden_after_the_move(scenario, curve):
    """The test move turns Faulty's flank into self-occlusion: Helper says so (currPart), Faulty
    turns by a known angle to show its flank and takes that turn out of what Helper sees."""
    start = 68.0 if curve > 0 else 124.0                  # ends within 5 degrees of +90
    world = World(scenario, bearing=-40.0, relative_heading=start - 2 * curve, curve=curve)
    diagnosis, out = diagnosis_of(world)
    assert "currPart(" in out, out
    assert "to show my flank" in out, out
    assert diagnosis == scenario, out


@pytest.mark.parametrize("scenario", ["right_actuator", "left_actuator", "both_actuators",
                                      "odometry"])
def test_sight_lost_after_the_move_is_never_reported_as_current(scenario):
    """The thesis reported the last kept position as current: a real fault became
    false_positive. Now the feedback says sight was lost and no component is named."""
    world = World(scenario, bearing=45.0)
    world.vanish_on_move = 3                              # the test move
    diagnosis, out = diagnosis_of(world)
    assert "currLost" in out, out
    assert diagnosis == "unknown", out


@pytest.mark.parametrize("scenario,curve,start", [("right_actuator", 16.0, 70.0),
                                                   ("left_actuator", -16.0, 120.0)])
def test_weak_view_near_occlusion_is_looked_at_again(scenario, curve, start):
    """The test move ends near the occlusion angle, where the yaw is biased (6 degrees here):
    the turn looks too close to call, so Faulty turns away by a known angle and Helper looks
    again; the second look names the component."""
    world = World(scenario, bearing=20.0, relative_heading=start - 2 * curve, curve=curve)
    world.occlusion_bias = 6.0
    diagnosis, out = diagnosis_of(world)
    assert "to show my flank" in out, out    # (after the move: hidden, or seen near occlusion)
    assert diagnosis == scenario, out


def test_turn_close_to_the_limit_names_no_component():
    for curve in (6.0, 10.0, -6.0, -10.0):
        diagnosis, out = diagnosis_of(World("right_actuator", curve=curve))
        assert diagnosis == "unknown", out
        assert "too close to the limit" in out


@pytest.mark.parametrize("odom_bearings", [False, True])
@pytest.mark.parametrize("bearing", [-150.0, -100.0, -30.0, 0.0, 120.0, 179.0])
def test_found_from_any_bearing_within_one_turn(bearing, odom_bearings):
    world = World("right_actuator", bearing=bearing, relative_heading=-90.0 - 40.0)
    world.odom_bearings = odom_bearings
    diagnosis, out = diagnosis_of(world)
    assert diagnosis == "right_actuator", out
    sweeps = [t for t in world.helper_turns if abs(t) == 360]
    centring = [t for t in world.helper_turns if abs(t) < 360]
    # at most one sweep, cut short at the first sighting, then a few small centring turns
    assert len(sweeps) <= 1 and sum(abs(t) for t in centring) < 60.0, (world.helper_turns, out)
    assert (len(sweeps) == 0) == (abs(bearing) < FOV_HALF), world.helper_turns


@pytest.mark.parametrize("bearing", [-60.0, -150.0, 100.0])
def test_sighting_braked_past_is_turned_back_to(bearing):
    """A fast sweep brakes (and coasts while the frame is processed) 62 degrees past the
    sighting, and Faulty leaves the view: Helper turns back to the heading where it saw it
    (turn_to, from seen_at), without a second sweep, and centres it."""
    world = World("right_actuator", bearing=bearing, relative_heading=-90.0 - 40.0)
    world.odom_bearings = True
    world.brake = 62.0
    diagnosis, out = diagnosis_of(world)
    assert [t for t in world.helper_turns if abs(t) == 360] == [360.0], world.helper_turns
    back = [t for t in world.helper_turns if abs(t) < 360]
    assert back and back[0] < -20.0, world.helper_turns     # back against the sweep
    assert abs(wrap(world.bearing - world.heading)) < FOV_HALF, world.helper_turns
    assert diagnosis == "right_actuator", out


def test_far_away_helper_moves_closer_first():
    world = World("left_actuator", bearing=10.0, distance=3.9, relative_heading=-50.0,
                  curve=-20.0)
    diagnosis, out = diagnosis_of(world)
    assert "m for a better view" in out, out
    assert 1.5 < world.distance < 2.2
    assert diagnosis == "left_actuator", out


def test_out_of_range_is_not_found():
    world = World("right_actuator", bearing=90.0, distance=4.8)
    diagnosis, out = diagnosis_of(world)
    # the sweep, then a look every 45 degrees of the circle (8 looks, 7 steps between them)
    steps = [t for t in world.helper_turns if abs(t) < 360]
    assert [abs(t) for t in steps] == [45.0] * 7, world.helper_turns
    assert "Nothing seen while sweeping: looking around faulty every 45 degrees" in out, out
    assert "Turned 360 degrees without finding faulty" in out
    assert diagnosis == "unknown", out


@pytest.mark.parametrize("bearing", [-150.0, -60.0, 60.0, 90.0, 170.0])
@pytest.mark.parametrize("stamps", [False, True])
def test_a_sweep_too_fast_for_the_camera_is_followed_by_looks(bearing, stamps):
    """No frame taken during the sweep shows Faulty (frames too seldom for 120 deg/s): Helper
    looks again from every 45 degrees, each look from a frame taken there at rest (with stamps,
    0.4 s late), finds Faulty and the diagnosis is right."""
    world = World("left_actuator", bearing=bearing, relative_heading=-50.0, curve=-20.0)
    world.odom_bearings = True
    world.blind_sweep = True
    if stamps:
        world.stamps, world.step_s, world.latency_ms = True, 0.02, 400.0
    diagnosis, out = diagnosis_of(world)
    assert "Nothing seen while sweeping" in out, out
    assert "Turned 360 degrees without finding" not in out, out
    assert abs(wrap(world.bearing - world.heading)) < FOV_HALF, world.helper_turns
    assert diagnosis == "left_actuator", out


# -- late frames (issue 15, F10): observations from frames taken at rest, after they started -------

def late_frames_world(scenario: str, latency_ms: float, **layout) -> World:
    world = World(scenario, **layout)
    world.odom_bearings = True
    world.stamps = True
    world.step_s = 0.02          # Helper turns TURN_STEP = 2 degrees in 20 ms: 100 deg/s
    world.latency_ms = latency_ms
    return world


def ready_position(out: str) -> tuple[float, float, float]:
    """Helper's initial observation, from its 'I'm ready: faulty is at pos(Deg,Depth,Yaw)'."""
    line = [t for t in out.splitlines() if "I'm ready: faulty is at pos(" in t][-1]
    deg, depth, yaw = line.split("pos(")[1].split(")")[0].split(",")
    return float(deg), float(depth), float(yaw)


@pytest.mark.parametrize("latency_ms", [0.0, 400.0, 900.0, 1400.0])
@pytest.mark.parametrize("scenario,curve", [("right_actuator", 20.0), ("left_actuator", -20.0),
                                            ("odometry", 0.0), ("both_actuators", 0.0)])
def test_late_frames_from_a_turning_camera_are_not_observed(scenario, curve, latency_ms):
    """Frames reach Helper up to 1.4 s after they were taken; those taken while it centred
    Faulty (a 40-degree turn) show Faulty where it no longer is. Helper's initial observation
    averages only frames taken at rest after it started, so it sees Faulty centred (where it
    faces it now), and the diagnosis is right."""
    world = late_frames_world(scenario, latency_ms, bearing=40.0, relative_heading=-90.0 - 40.0,
                              curve=curve)
    diagnosis, out = diagnosis_of(world)
    assert world.helper_turns and abs(world.helper_turns[0]) > 30.0, world.helper_turns
    deg, _, _ = ready_position(out)
    assert abs(deg) < 7.0, out
    assert diagnosis == scenario, out


def test_frames_from_before_faultys_move_ended_are_not_observed():
    """Frames 0.9 s late: when Helper is asked to track Faulty, and when Faulty asks for
    feedback, the newest frames Helper has show Faulty before its last move. Each observation
    counts only frames stamped after it started (plus settleTime), so the two observations
    enclose exactly the test move: the 20-degree turn of that one move is what Faulty sees
    (frames from before its first moves gave 40: two moves)."""
    world = late_frames_world("right_actuator", 900.0, bearing=0.0, relative_heading=-90.0 - 40.0,
                              curve=20.0)
    diagnosis, out = diagnosis_of(world)
    assert "): turned 20" in out, out
    assert diagnosis == "right_actuator", out
