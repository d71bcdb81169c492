"""Default plans for KQML performatives (Jason's ``kqmlPlans.asl``), appended to every agent.

As in Jason, ``tell`` and ``achieve`` are handled directly; the other performatives become a
``+!kqml_received(Sender, Performative, Content, MsgId)`` event handled by these plans, which a
program may override with its own ``kqml_received`` plans.
"""

KQML_PLANS = r"""
@kqmlReceivedUnTell
+!kqml_received(Sender, untell, Content, _)
   <- .add_nested_source(Content, Sender, CA);
      -CA.

@kqmlReceivedUnAchieve[atomic]
+!kqml_received(_, unachieve, Content, _)
   <- .drop_desire(Content).

@kqmlReceivedAskOne1a
+!kqml_received(Sender, askOne, Content, MsgId)
    : .remove_source_annot(Content, C2) & C2[source(self)]
   <- .send(Sender, tell, C2, MsgId).

@kqmlReceivedAskOne1b
+!kqml_received(Sender, askOne, Content, MsgId)
    : Content[source(AGS)]
   <- .send(Sender, tell, Content[source(AGS)], MsgId).

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
   <- .findall(Content[source(AGS)], Content[source(AGS)], List);
      .clear_source_self(List, L2);
      .send(Sender, tell, L2, MsgId).

@kqmlReceivedSignal
+!kqml_received(Sender, signal, Content, _)
   <- .add_nested_source(Content, Sender, CA);
      .signal(CA).

@kqmlError
-!kqml_received(_Sender, _Per, _Content, _MsgId)[error(EID), error_msg(EMsg)]
   <- .print("Communication error -- ", EID, ": ", EMsg).
"""

_cache: list = []


def kqml_plans() -> list:
    """The parsed default plans (parsed once)."""
    if not _cache:
        from .parser import parse_source
        _cache.extend(parse_source(KQML_PLANS, "kqmlPlans.asl", src="file:kqmlPlans.asl").plans)
    return list(_cache)
