"""Default plans for KQML performatives (Jason's ``kqmlPlans.asl``), appended to every agent.

As in Jason (``TransitionSystem.applyProcMsg``), a ``tell``/``achieve``/``signal`` of one literal is
handled directly unless the program has its own ``kqml_received`` plans; everything else becomes
a ``+!kqml_received(Sender, Performative, Content, MsgId)`` event handled by these plans (after the
program's own).
"""

import os
import pickle
import re
import zlib

from .parser import parse_source, user_cache_folder
from .plans import Plan, named_plan
from .terms import ListTerm, Literal, PlanTerm, Var, make_list, source
from .unify import rename_vars

KQML_PLANS = r"""
// The content of a message keeps its namespace: NS::Content takes it apart (a plain
// variable only holds literals of the default namespace) and each plan puts it back.
@kqmlReceivedTellStructure[atomic]
+!kqml_received(Sender, tell, NS::Content, _)
   :  .literal(Content) & .ground(Content) & not .list(Content) &
      .add_nested_source(Content, Sender, CA)
   <- ++NS::CA.

@kqmlReceivedTellList
+!kqml_received(Sender, tell, Content, _)
   :  .list(Content)
   <- !add_all_kqml_received(Sender, Content).

@kqmlReceivedTellList1
+!add_all_kqml_received(_, []).

@kqmlReceivedTellList2
+!add_all_kqml_received(Sender, [NS::H|T])
   :  .literal(H) & .ground(H)
   <- .add_nested_source(H, Sender, CA);
      ++NS::CA;
      !add_all_kqml_received(Sender, T).

@kqmlReceivedTellList3
+!add_all_kqml_received(Sender, [_|T])
   <- !add_all_kqml_received(Sender, T).

@kqmlReceivedUnTell[atomic]
+!kqml_received(Sender, untell, NS::Content, _)
   :  .add_nested_source(Content, Sender, CA)
   <- --NS::CA.

@kqmlReceivedAchieve
+!kqml_received(Sender, achieve, NS::Content, _)
   :  not .list(Content) & .add_nested_source(Content, Sender, CA)
   <- !!NS::CA.

@kqmlReceivedAchieveList
+!kqml_received(Sender, achieve, Content, _)
   :  .list(Content)
   <- !add_all_kqml_achieve(Sender, Content).

@kqmlReceivedAchieveList1
+!add_all_kqml_achieve(_, []).

@kqmlReceivedAchieveList2
+!add_all_kqml_achieve(Sender, [NS::H|T])
   <- .add_nested_source(H, Sender, CA);
      !!NS::CA;
      !add_all_kqml_achieve(Sender, T).

@kqmlReceivedUnAchieve[atomic]
+!kqml_received(_, unachieve, NS::Content, _)
   <- .drop_desire(NS::Content).

@kqmlReceivedAskOne1d
+!kqml_received(Sender, askOne, NS::Content, MsgId)
   :  .kqml_belief_answer(NS, Content, Ans)
   <- .send(Sender, tell, NS::Ans, MsgId).

@kqmlReceivedAskOne1c
+!kqml_received(Sender, askOne, NS::Content, MsgId)
   <- .add_nested_source(Content, Sender, CA);
      ?NS::CA;
      .remove_source_annot(CA, CA2);
      .send(Sender, tell, NS::CA2, MsgId).

@kqmlReceivedAskOne2
-!kqml_received(Sender, askOne, NS::Content, MsgId)[error(test_goal_failed)]
   <- .send(Sender, untell, NS::Content, MsgId).

@kqmlReceivedAskAll2
+!kqml_received(Sender, askAll, NS::Content, MsgId)
   <- .findall(NS::Ans, .kqml_belief_answer(NS, Content, Ans), List);
      .send(Sender, tell, List, MsgId).

@kqmlReceivedTellHow
+!kqml_received(Sender, tellHow, Content, _)
   <- .remove_source_annot(Content, ContentAn);
      .add_plan(ContentAn, Sender).

@kqmlReceivedUnTellHow
+!kqml_received(Sender, untellHow, Content, _)
   <- .remove_plan(Content, Sender).

@kqmlReceivedAskHow
+!kqml_received(Sender, askHow, Content, MsgId)
   <- .relevant_plans(Content, ListOfPlans);
      .remove_source_annot(ListOfPlans, ListOfPlansAn);
      .send(Sender, tellHow, ListOfPlansAn, MsgId).

@kqmlReceivedSignal
+!kqml_received(Sender, signal, NS::Content, _)
   :  not .list(Content) & .add_nested_source(Content, Sender, CA)
   <- .signal(NS::CA).

@kqmlError
-!kqml_received(_Sender, _Per, _Content, _MsgId)[error(EID), error_msg(EMsg)]
   <- .print("Communication error -- ", EID, ": ", EMsg).
"""

#: the ``src`` of the default plans (a program's own ``kqml_received`` plans have another one):
#: their labels' ``url("kqmlPlans.asl")``, as Jason's (a resource of its jar, no ``file:``)
KQML_SRC = "kqmlPlans.asl"

_cache: list = []


def kqml_plans() -> list:
    """The parsed default plans (parsed once per process; kept between runs, see
    :func:`_stored_plans`)."""
    if not _cache:
        _cache.extend(_stored_plans())
    return list(_cache)


#: how the parser names an anonymous variable ``_`` (:func:`~rason.asl.terms.fresh_name`)
_ANONYMOUS = re.compile(r"_[0-9]+")


def _with_fresh_anonymous(plan: Plan) -> Plan:
    """``plan`` (read from another process) with its anonymous variables named anew (the named
    ones are kept)."""
    renaming: dict[str, Var] = {}
    return plan.map_terms(lambda t: rename_vars(
        t, renaming, lambda name: _ANONYMOUS.fullmatch(name) is not None))


def _module_stamps(folder: str) -> list[tuple[str, int, int]]:
    """Name, size and modification time (ns) of every ``.py`` file under ``folder``, sorted
    by path (os.scandir: a start-up pays this, and pathlib's walk costs several times more)."""
    found: list[tuple[str, str, int, int]] = []
    pending = [folder]
    while pending:
        with os.scandir(pending.pop()) as entries:
            for entry in entries:
                if entry.is_dir(follow_symlinks=False):
                    if entry.name != "__pycache__":
                        pending.append(entry.path)
                elif entry.name.endswith(".py"):
                    stat = entry.stat()
                    found.append((entry.path, entry.name, stat.st_size, stat.st_mtime_ns))
    return [(name, size, mtime) for _, name, size, mtime in sorted(found)]


def _stored_plans() -> list[Plan]:
    """The default plans parsed by an earlier run (a pickle in the user's cache folder, about
    6x faster than parsing them), else parsed now and stored. The file holds the stamp it was
    made for (the plans' text and the stamps of every rason.asl module; its name a checksum of
    it), so any change parses again; anonymous variables get names fresh in this process."""
    # every module of rason.asl: a pickled class may live in any of them
    stamp = "\n".join([KQML_PLANS] + [f"{name}:{size}:{mtime}" for name, size, mtime
                                      in _module_stamps(os.path.dirname(os.path.abspath(__file__)))])
    folder = user_cache_folder()
    # a checksum names the file (hashlib's import alone would cost a fifth of reading it)
    path = (None if folder is None
            else os.path.join(folder, f"kqml-{zlib.crc32(stamp.encode('utf-8')):08x}.pickle"))
    if path is not None and os.path.isfile(path):
        try:
            with open(path, "rb") as f:
                stored_stamp, stored = pickle.load(f)
            if stored_stamp == stamp:
                return [_with_fresh_anonymous(p) for p in stored]
        except (OSError, pickle.UnpicklingError, EOFError, AttributeError, TypeError, ValueError):
            pass                               # unreadable: parse again and store anew
    parsed = parse_source(KQML_PLANS, "kqmlPlans.asl", src=KQML_SRC).plans
    if path is not None:
        try:
            partial = f"{path}.{os.getpid()}.tmp"    # agents often start together
            with open(partial, "wb") as f:
                pickle.dump((stamp, parsed), f, protocol=pickle.HIGHEST_PROTOCOL)
            os.replace(partial, path)
        except (OSError, pickle.PicklingError, TypeError, AttributeError):
            pass                               # a read-only cache folder: parse every time
    return parsed


def plans_answered_by(content: ListTerm, sender: str) -> ListTerm:
    """The plans of an askHow answer as the asker gets them (Jason's TransitionSystem): each
    plan's label names the sender as its source; what is not a plan is left out."""
    out = []
    for t in content.items:
        if not isinstance(t, PlanTerm) or t.plan is None:
            continue
        plan = named_plan(t.plan)
        label = plan.label if isinstance(plan.label, Literal) else Literal("p__")
        annots = [a for a in label.annots if not (isinstance(a, Literal) and a.functor == "source")]
        label = label.with_annots(()).add_annots([source(sender), *annots])
        made = Plan(label, plan.trigger, plan.context, plan.body, plan.line, plan.src,
                    in_file=plan.in_file, goal_condition=plan.goal_condition)
        out.append(made.as_term())
    return make_list(out)
