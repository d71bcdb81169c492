"""The agent language's ahead-of-time parser (rason.asl.lalr with the generated asl_tables)
against lark's own LALR parser with its contextual lexer, built from the same grammar: the
tables must be those of the grammar, and both parsers must make the same objects, or the same
error at the same place, for every text."""

from __future__ import annotations

import glob
import os
import random
import re
import subprocess
import sys

import pytest
from asl_helpers import CONFORMANCE
from lark import Lark
from lark import Token as LarkToken
from lark.exceptions import UnexpectedInput as LarkUnexpectedInput

from rason.asl import asl_tables, lalr
from rason.asl.kqml import KQML_PLANS
from rason.asl.lalr_gen import module_text, reference_lark
from rason.asl.parser import (
    _BUILDER,
    _PARSE_LOCK,
    GRAMMAR,
    _get_parser,
    _ReduceBuilder,
    _SemErr,
    _ToAst,
    describe_syntax_error,
)

#: the rule builder lark's parser drives (the parser's own serves ours)
LARK_BUILDER = _ReduceBuilder(LarkToken)

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))


def _read(path: str) -> str:
    with open(path, encoding="utf-8") as f:
        return f.read()


PROGRAMS = [_read(p) for p in sorted(glob.glob(os.path.join(CONFORMANCE, "*", "*.asl")))]
PROGRAMS += [_read(p) for p in sorted(glob.glob(os.path.join(ROOT, "**", "*.asl"), recursive=True))
             if "/.venv/" not in p]
PROGRAMS.append(KQML_PLANS)

#: texts where the parser's state decides what a token is (lark's contextual lexer)
TRICKY = [
    "+!g : X<-1 <- .print(X).", "+!g <- X = Y<-1.", "+!g <- .print(X mod 2, X div 3).",
    "+!g <- !not.", "+!g <- !nothing; ?notice(X).", "+!g : not not p <- true.",
    "a:-b.", "a :- not b & c | d.", "+!g : -1 < X <- .print(x).", "+!g <- X = -+1.",
    "+!g <- -+b(1); --b; ++c; !!d; ?e.", "{+!g <- .print}", "+!g <- A = {+!h <- .print(x)}.",
    "'quoted atom'(1).", "p('it''s').", "+!g <- .print(\"a\nb\").", "/* a\n b */ p. // c",
    "p([H|T]).", "p([a||b]).", "+!g <- a ||| b |&| c.", "+!g <- if (X) { a } elif (Y) { b } else { c }.",
    "+!g <- while (X < 3) { X = X + 1 }; for (.member(X, [1,2])) { .print(X) }.",
    "div::p.", "ns::p(X) :- X::q.", "X::p.", "+!g <- N::b(X); ::c; default::d.", "p(a) [x].",
    "+!g <- X = 1.5e3 ** -2.", "p(X) :- X =.. [a, b].", "+!g <- X \\== Y; X == Y; X >= Y; X <= Y.",
    "@l[atomic] +!g <- true.", "@p +!g.", "+!g <: done <- .print.", "^!g[state(S)] <- .print(S).",
    "{ include(\"x.asl\") }", "{ begin namespace(ns, local) } p. { end }", "+p <- .print(1 mod-1).",
    "+!g <- .print(1-1);-b.", "+!g <- X=.1.", "p(.a.b).", "+!g <- .a.b.c(1).", "+!g <- .print(x)..",
    "p(", "p(1", "+!g <- ", "+!g <- if (X) {", "\"unterminated", "p(1) :- .", "p. $", "p. q(#)",
    "", "   ", "// only a comment", "/* open comment", "@", "+!", "+!g : <- .", "!g(X)", "p.q.",
]

#: pieces of texts for random ones, written next to each other (no spaces: the lexer decides)
PIECES = ["+", "-", "!", "!!", "?", "-+", "++", "--", "<-", ":-", "<:", ":", "::", ".", ";", ",",
          "(", ")", "[", "]", "{", "}", "|", "|||", "|&|", "&", "not", "if", "elif", "else", "while",
          "for", "@", "~", "=", "==", "\\==", "=..", "<", "<=", ">", ">=", "*", "**", "/", "div",
          "mod", "X", "Y_1", "_", "a", "ns", "p(1)", ".print", "\"s\"", "'q'", "1.5e3", "2", "\n",
          " ", "//c\n", "/*", "*/", "\\", "^", "nothing", "notably", "format", "divide", "modest"]


def _normal(text: str) -> str:
    """A made object's text without what differs from run to run (fresh names, addresses)."""
    return re.sub(r" at 0x[0-9a-f]+", "", re.sub(r"\b_\d+\b", "_N", text))


def _outcome(parse, builder: _ReduceBuilder, text: str) -> tuple:
    """What ``parse`` (ours or lark's, driving ``builder``) makes of text."""
    with _PARSE_LOCK:
        builder.ast = _ToAst("t.asl")
        try:
            return ("made", _normal(repr(parse(text))))
        except _SemErr as e:
            return ("rejected", e.line, e.col, e.msg)
        except (lalr.UnexpectedInput, LarkUnexpectedInput) as e:
            return ("syntax error", e.line, e.column, describe_syntax_error(e))
        finally:
            builder.ast = None
            builder.positions.clear()
            builder.made.clear()


@pytest.fixture(scope="module")
def lark_parser() -> Lark:
    return Lark(GRAMMAR, parser="lalr", lexer="contextual", maybe_placeholders=True, transformer=LARK_BUILDER)


def test_tables_are_those_of_the_grammar() -> None:
    """asl_tables.py is what ``python -m rason.asl.lalr_gen`` writes for today's GRAMMAR
    (regenerate it after changing the grammar)."""
    assert _read(asl_tables.__file__) == module_text(GRAMMAR)


def test_each_state_lexes_with_lark_terminals_and_keywords() -> None:
    """For every lexing context of lark's contextual lexer, our scanner tries the same terminals
    in the same order and tells the same keywords apart."""
    contexts = reference_lark(GRAMMAR).parser.lexer.lexers.values()
    seen = set()
    for lexer in contexts:
        names = frozenset(t.name for t in lexer.terminals)
        if names in seen:
            continue
        seen.add(names)
        ours = lalr._Scanner(asl_tables, names)
        theirs = lexer.scanner
        assert len(theirs._mres) == 1
        assert ours.match.__self__.pattern == theirs._mres[0].pattern
        assert ours.allowed == theirs.allowed_types - lexer.ignore_types
        theirs_unless = {kind: {v: k for k, v in _unless(cb).items()} for kind, cb in lexer.callback.items()}
        assert ours.unless == theirs_unless
    assert len(seen) > 10


def _unless(callback) -> dict[str, str]:
    """Keyword -> its text, from a lark ``UnlessCallback``."""
    mre = callback.scanner._mres[0]
    return {name: re.sub(r"\\(.)", r"\1", re.search(rf"\(\?P<{name}>(.*?)\)(\||$)", mre.pattern).group(1))
            for name in mre.groupindex}


@pytest.mark.parametrize("text", PROGRAMS + TRICKY, ids=lambda t: _normal(t[:30]))
def test_same_result_as_lark(lark_parser: Lark, text: str) -> None:
    assert _outcome(_get_parser().parse, _BUILDER, text) == _outcome(lark_parser.parse, LARK_BUILDER, text)


def test_same_result_as_lark_on_random_texts(lark_parser: Lark) -> None:
    """Random texts and mutated programs: same objects or same error at the same place."""
    rng = random.Random(19)
    texts = ["".join(rng.choice(PIECES) for _ in range(rng.randint(1, 30))) for _ in range(1500)]
    for program in PROGRAMS[:40]:
        for _ in range(10):
            chars = list(program)
            for _ in range(rng.randint(1, 3)):
                i = rng.randrange(len(chars) + 1)
                if rng.random() < 0.5 and i < len(chars):
                    del chars[i]
                else:
                    chars.insert(i, rng.choice(PIECES))
            texts.append("".join(chars))
    made = errors = 0
    for text in texts:
        ours = _outcome(_get_parser().parse, _BUILDER, text)
        assert ours == _outcome(lark_parser.parse, LARK_BUILDER, text), text
        made += ours[0] == "made"
        errors += ours[0] != "made"
    assert made > 100 and errors > 100     # both paths are exercised


def test_a_lone_agent_runs_without_importing_lark(tmp_path) -> None:
    # lark (about 20 ms of an empty agent's start) is for the project reader and the generator
    (tmp_path / "a.asl").write_text("!s.\n+!s <- .print(done).\n")
    script = ("import runpy, sys\nsys.argv = ['rason.asl', 'run', sys.argv[1]]\n"
              "try:\n    runpy.run_module('rason.asl', run_name='__main__')\nexcept SystemExit:\n    pass\n"
              "print(' '.join(m for m in sys.modules if m == 'lark' or m.startswith('lark.')))\n")
    done = subprocess.run([sys.executable, "-c", script, str(tmp_path / "a.asl")],
                          capture_output=True, text=True, timeout=60, check=True)
    assert done.stdout.splitlines() == ["[a] done", ""], done.stdout
