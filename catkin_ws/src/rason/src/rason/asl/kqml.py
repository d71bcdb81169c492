"""Default plans for KQML performatives (Jason's ``kqmlPlans.asl``), appended to every agent.

As in Jason (``TransitionSystem.applyProcMsg``), a ``tell``/``achieve``/``signal`` of one literal is
handled directly unless the program has its own ``kqml_received`` plans; everything else becomes
a ``+!kqml_received(Sender, Performative, Content, MsgId)`` event handled by these plans (after the
program's own).
"""

from .parser import parse_source

KQML_PLANS = r"""
@kqmlReceivedTellStructure[atomic]
+!kqml_received(Sender, tell, Content, _)
   :  .literal(Content) & .ground(Content) & not .list(Content) &
      .add_nested_source(Content, Sender, CA)
   <- ++CA.

@kqmlReceivedTellList
+!kqml_received(Sender, tell, Content, _)
   :  .list(Content)
   <- !add_all_kqml_received(Sender, Content).

@kqmlReceivedTellList1
+!add_all_kqml_received(_, []).

@kqmlReceivedTellList2
+!add_all_kqml_received(Sender, [H|T])
   :  .literal(H) & .ground(H)
   <- .add_nested_source(H, Sender, CA);
      ++CA;
      !add_all_kqml_received(Sender, T).

@kqmlReceivedTellList3
+!add_all_kqml_received(Sender, [_|T])
   <- !add_all_kqml_received(Sender, T).

@kqmlReceivedUnTell[atomic]
+!kqml_received(Sender, untell, Content, _)
   :  .add_nested_source(Content, Sender, CA)
   <- --CA.

@kqmlReceivedAchieve
+!kqml_received(Sender, achieve, Content, _)
   :  not .list(Content) & .add_nested_source(Content, Sender, CA)
   <- !!CA.

@kqmlReceivedAchieveList
+!kqml_received(Sender, achieve, Content, _)
   :  .list(Content)
   <- !add_all_kqml_achieve(Sender, Content).

@kqmlReceivedAchieveList1
+!add_all_kqml_achieve(_, []).

@kqmlReceivedAchieveList2
+!add_all_kqml_achieve(Sender, [H|T])
   <- .add_nested_source(H, Sender, CA);
      !!CA;
      !add_all_kqml_achieve(Sender, T).

@kqmlReceivedUnAchieve[atomic]
+!kqml_received(_, unachieve, Content, _)
   <- .drop_desire(Content).

@kqmlReceivedAskOne1d
+!kqml_received(Sender, askOne, Content, MsgId)
   :  .kqml_belief_answer(Content, Ans)
   <- .send(Sender, tell, Ans, MsgId).

@kqmlReceivedAskOne1c
+!kqml_received(Sender, askOne, Content, MsgId)
   <- .add_nested_source(Content, Sender, CA);
      ?CA;
      .remove_source_annot(CA, CA2);
      .send(Sender, tell, CA2, MsgId).

@kqmlReceivedAskOne2
-!kqml_received(Sender, askOne, Content, MsgId)[error(test_goal_failed)]
   <- .send(Sender, untell, Content, MsgId).

@kqmlReceivedAskAll2
+!kqml_received(Sender, askAll, Content, MsgId)
   <- .findall(Ans, .kqml_belief_answer(Content, Ans), List);
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
+!kqml_received(Sender, signal, Content, _)
   :  not .list(Content) & .add_nested_source(Content, Sender, CA)
   <- .signal(CA).

@kqmlError
-!kqml_received(_Sender, _Per, _Content, _MsgId)[error(EID), error_msg(EMsg)]
   <- .print("Communication error -- ", EID, ": ", EMsg).
"""

#: the ``src`` of the default plans (a program's own ``kqml_received`` plans have another one)
KQML_SRC = "file:kqmlPlans.asl"

_cache: list = []


def kqml_plans() -> list:
    """The parsed default plans (parsed once)."""
    if not _cache:
        _cache.extend(parse_source(KQML_PLANS, "kqmlPlans.asl", src=KQML_SRC).plans)
    return list(_cache)
