#!/usr/bin/env python3
# ruff: noqa  (verbatim copy of ../shared/conformance/compare.py)
"""Compare AgentSpeak interpreter output with the Jason conformance suite.

Usage:
  python3 compare.py CASE_DIR ACTUAL_OUTPUT_FILE
      Exit 0 if, for every agent, the sequence of that agent's lines in
      ACTUAL_OUTPUT_FILE equals the sequence in CASE_DIR/expected.txt;
      otherwise print a unified diff (grouped per agent) and exit 1.

  python3 compare.py --suite DIR --cmd 'COMMAND {entry}' [--jobs N] [--timeout S] [-v]
      Run COMMAND once per case found under DIR (any folder holding
      expected.txt plus project.mas2j or main.asl). {entry} is replaced by the
      absolute path of the case's project.mas2j (if present) or main.asl;
      {dir} by the absolute case folder. The command runs through the shell
      with cwd = case folder and a timeout (default 20 s); only its stdout is
      compared. Prints PASS/FAIL per case and a final line "N passed, M failed";
      exits 0 only if nothing failed. --suite may be repeated.

Output format: every record starts with "[agent] " (agent name in square
brackets and one space, as Jason's MASConsoleLogFormatter writes it). A line
that does not start with "[name] " is a continuation of the previous record
(multi-line messages, e.g. a printed string holding a newline or Jason's
intention dumps) and belongs to the same agent. Lines are compared exactly
(only a trailing carriage return is dropped); --ignore-trailing-space relaxes
that. Interleaving between different agents is NOT compared: only each agent's
own subsequence must match. Jason's warnings about a dropped intention
("No failure event was generated ...", with its intention dump) are left out
of the comparison unless --strict is given: the lines around them still show
whether the intention was dropped and the agent lived on.
"""
import argparse
import difflib
import os
import re
import shlex
import signal
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor

RECORD_RE = re.compile(r'^\[([^\]\s]+)\](?: |$)')
NO_AGENT = '<no agent>'


def split_lines(text):
    lines = text.split('\n')
    if lines and lines[-1] == '':
        lines.pop()
    return [l[:-1] if l.endswith('\r') else l for l in lines]


# Jason's warnings about a dropped intention (and the intention dump that follows them) are
# diagnostics, not program output: both sides drop them unless --strict is given.
WARNING_STARTS = ('No failure event was generated', 'No fail event was generated',
                  'Found a goal for which there is no')


def records(text, rstrip=False):
    """List of (agent, [lines]) records: a '[name] ' line and its continuation lines."""
    recs = []
    for line in split_lines(text):
        if rstrip:
            line = line.rstrip()
        m = RECORD_RE.match(line)
        if m or not recs:
            recs.append((m.group(1) if m else NO_AGENT, [line]))
        else:
            recs[-1][1].append(line)
    return recs


def is_warning(lines):
    body = RECORD_RE.sub('', lines[0], count=1)
    if body.startswith(WARNING_STARTS):
        return True
    return body == '' and len(lines) > 1 and lines[1].startswith('intention ')


def per_agent(text, rstrip=False, strict=False):
    """Map agent name -> list of its lines (continuation lines included)."""
    groups = {}
    for agent, lines in records(text, rstrip):
        if not strict and is_warning(lines):
            continue
        groups.setdefault(agent, []).extend(lines)
    return groups


def grouped_view(groups):
    out = []
    for ag in sorted(groups):
        out.extend(groups[ag])
    return out


def compare_text(expected, actual, rstrip=False, strict=False):
    """Return (ok, diff_lines)."""
    e = per_agent(expected, rstrip, strict)
    a = per_agent(actual, rstrip, strict)
    if e == a:
        return True, []
    diff = list(difflib.unified_diff(grouped_view(e), grouped_view(a),
                                     'expected (per agent)', 'actual (per agent)',
                                     lineterm=''))
    return False, diff


def read(path):
    with open(path, encoding='utf-8', errors='replace', newline='') as f:
        return f.read()


def find_entry(case_dir):
    for name in ('project.mas2j', 'main.asl'):
        p = os.path.join(case_dir, name)
        if os.path.isfile(p):
            return p
    return None


def find_cases(root):
    cases = []
    for dirpath, dirnames, filenames in os.walk(root):
        dirnames.sort()
        if 'expected.txt' in filenames and find_entry(dirpath):
            cases.append(os.path.abspath(dirpath))
            dirnames[:] = []
    return sorted(cases)


def run_case(case_dir, cmd_template, timeout):
    entry = find_entry(case_dir)
    cmd = cmd_template.replace('{entry}', shlex.quote(entry)).replace('{dir}', shlex.quote(case_dir))
    proc = subprocess.Popen(cmd, shell=True, cwd=case_dir, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, start_new_session=True)
    timed_out = False
    try:
        out, err = proc.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        timed_out = True
        try:
            os.killpg(proc.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
        out, err = proc.communicate()
    out = out.decode('utf-8', errors='replace')
    err = err.decode('utf-8', errors='replace')
    return out, err, proc.returncode, timed_out


def suite_main(args):
    cases = []
    for root in args.suite:
        if not os.path.isdir(root):
            print(f'no such directory: {root}', file=sys.stderr)
            return 2
        cases.extend(find_cases(root))
    if not cases:
        print('no cases found', file=sys.stderr)
        return 2
    base = os.path.commonpath(cases) if len(cases) > 1 else os.path.dirname(cases[0])

    def job(case):
        out, err, rc, timed_out = run_case(case, args.cmd, args.timeout)
        ok, diff = compare_text(read(os.path.join(case, 'expected.txt')), out,
                                args.ignore_trailing_space, args.strict)
        if timed_out:
            ok = False
        return case, ok, diff, out, err, rc, timed_out

    with ThreadPoolExecutor(max_workers=max(1, args.jobs)) as ex:
        results = list(ex.map(job, cases))

    passed = failed = 0
    for case, ok, diff, out, err, rc, timed_out in results:
        name = os.path.relpath(case, base)
        if ok:
            passed += 1
            print(f'PASS {name}')
            continue
        failed += 1
        why = ' (timeout)' if timed_out else (f' (exit code {rc})' if rc else '')
        print(f'FAIL {name}{why}')
        if args.verbose:
            for line in diff:
                print('    ' + line)
            if err.strip():
                print('    --- stderr (last lines):')
                for line in err.strip().splitlines()[-10:]:
                    print('    ' + line)
    print(f'{passed} passed, {failed} failed')
    return 0 if failed == 0 else 1


def single_main(case_dir, actual_file, rstrip, strict):
    exp_path = os.path.join(case_dir, 'expected.txt')
    if not os.path.isfile(exp_path):
        print(f'no expected.txt in {case_dir}', file=sys.stderr)
        return 2
    ok, diff = compare_text(read(exp_path), read(actual_file), rstrip, strict)
    if ok:
        return 0
    for line in diff:
        print(line)
    return 1


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter,
                                 epilog=__doc__)
    ap.add_argument('case_dir', nargs='?')
    ap.add_argument('actual', nargs='?')
    ap.add_argument('--suite', action='append', metavar='DIR')
    ap.add_argument('--cmd', help="command template, e.g. 'myjason {entry}'")
    ap.add_argument('--timeout', type=float, default=20.0, help='seconds per case (default 20)')
    ap.add_argument('--jobs', type=int, default=1, help='cases run in parallel (default 1)')
    ap.add_argument('--ignore-trailing-space', action='store_true',
                    help='strip trailing whitespace of every line before comparing')
    ap.add_argument('--strict', action='store_true',
                    help="also compare Jason's warnings about dropped intentions, word for word")
    ap.add_argument('-v', '--verbose', action='store_true', help='show diffs of failing cases')
    args = ap.parse_args()
    if args.suite:
        if not args.cmd:
            ap.error('--suite needs --cmd')
        sys.exit(suite_main(args))
    if not (args.case_dir and args.actual):
        ap.error('give CASE_DIR ACTUAL_OUTPUT_FILE, or --suite DIR --cmd CMD')
    sys.exit(single_main(args.case_dir, args.actual, args.ignore_trailing_space, args.strict))


if __name__ == '__main__':
    main()
