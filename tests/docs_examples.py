#!/usr/bin/python3
"""Run the documentation's command examples and compare what lowpair prints with what the docs show.

    docs_examples.py --lowpair PATH --root SOURCE_DIR [FILE.md ...]

An example is a fenced code block of README.md or docs/*.md (or of the files named) whose first line starts
with `$ lowpair `. In it, a command starts with `$ ` and continues over lines ending in `\\`; the lines after
it, up to the next `$ ` line or the end of the block, are its expected output: what the command writes to
stdout, followed by what it writes to stderr (a rejected calibration shows its report, then the `error:`
line). The exit status is not compared (the docs say it in the prose); a command killed by a signal fails.

The commands of one Markdown file run in order, in a fresh temporary directory holding symlinks `models`,
`scenarios` and `tests` to the source tree: relative paths work, and files the examples write (m.csv,
cal.yaml) land there for the file's later commands. A command is split with shlex (a `# comment` after it is
dropped) and run as an argument vector, never through a shell; `lowpair` is replaced by --lowpair.

Comparison, line by line, after stripping trailing whitespace on both sides:
  - an expected line that is `...` (indentation allowed) matches any number of lines, none included;
  - wall-clock times are masked: a number followed by ` s` (`(0.010 s)`, `plan 1.597 s`) or by
    ` samples/s`;
  - numbers are equal when their text is, or when they differ by at most one unit in the last significant
    digit of the more precise one, counting at least two digits since %g drops trailing zeros (another
    CPU or compiler may round the last digit the other way; two
    plain integers, counts, ranks and line numbers, must be equal), or when both are at rounding level,
    |x| <= 1e-12, or both the reciprocal of it, |x| >= 1e12 (a condition number of a singular matrix):
    such numbers differ between builds, and the docs say so next to them; whitespace next to a number
    printed differently may differ in length;
  - everything else must be equal.

A block preceded (on the line right before its opening fence) by `<!-- docs-example: not run (REASON) -->`
is skipped and listed. Exit status: 0 every example matches; 1 a mismatch (the file, the line of the
command and a unified diff are printed); 2 bad usage or a malformed example; 77 (ctest's skip) when
LOWPAIR_SANITIZE is set: the sanitizer build runs at -O1 and prints other rounding-level digits.
"""

import argparse
import dataclasses
import difflib
import os
import re
import shlex
import subprocess
import sys
import tempfile
import time
from decimal import Decimal
from pathlib import Path

SKIP_EXIT = 77
LINKS = ("models", "scenarios", "tests")  # what the examples' relative paths reach in the source tree
COMMAND_TIMEOUT = 120  # seconds; the slowest example takes about 1 s
SKIP_MARKER = re.compile(r"^<!-- docs-example: not run \((?P<reason>.+)\) -->$")
FENCE = re.compile(r"^(?P<fence>`{3,}|~{3,})")
# a number: not part of a word or of a dotted name; a trailing `x` (4.93e+03x, a factor) is not part of it
NUMBER = re.compile(r"(?<![\w.])[-+]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][-+]?\d+)?(?:(?![\w.])|(?=x\b))")
TIMES = (re.compile(r"(?<![\w.])\d+(?:\.\d*)?(?:[eE][-+]?\d+)? s\b"),
         re.compile(r"(?<![\w.])\d+(?:\.\d*)?(?:[eE][-+]?\d+)? samples/s\b"))
ROUNDING_LEVEL = Decimal("1e-12")
ABOVE_ROUNDING = Decimal("1e12")


@dataclasses.dataclass
class Command:
    line: int  # 1-based line of the `$ ` line in the Markdown file
    lines: int  # the command's lines (continuations included)
    text: str  # the command, continuation lines joined
    expected: list


@dataclasses.dataclass
class Block:
    line: int  # 1-based line of the opening fence
    commands: list
    skip_reason: str = ""


class ExampleError(Exception):
    """A malformed example: exit 2."""


def parse_blocks(path, lines):
    """The fenced blocks of a Markdown file whose first line starts with `$ lowpair `."""
    blocks = []
    i = 0
    while i < len(lines):
        opening = FENCE.match(lines[i])
        if not opening:
            i += 1
            continue
        fence = opening.group("fence")
        end = i + 1
        while end < len(lines) and not (lines[end].startswith(fence[0] * len(fence))
                                        and lines[end].strip().strip(fence[0]) == ""):
            end += 1
        if end == len(lines):
            raise ExampleError(f"{path}:{i + 1}: code block not closed")
        body = lines[i + 1:end]
        if body and body[0].startswith("$ lowpair "):
            marker = SKIP_MARKER.match(lines[i - 1].strip()) if i > 0 else None
            blocks.append(Block(i + 1, parse_commands(path, i + 2, body),
                                marker.group("reason") if marker else ""))
        i = end + 1
    return blocks


def parse_commands(path, first_line, body):
    commands = []
    k = 0
    while k < len(body):
        line = body[k]
        if not line.startswith("$ "):
            raise ExampleError(f"{path}:{first_line + k}: expected a `$ ` command line")
        start = k
        text = line[2:]
        while text.endswith("\\"):
            k += 1
            if k == len(body):
                raise ExampleError(f"{path}:{first_line + start}: `\\` on the block's last line")
            text = text[:-1] + " " + body[k].strip()
        k += 1
        expected = []
        while k < len(body) and not body[k].startswith("$ "):
            expected.append(body[k])
            k += 1
        commands.append(Command(first_line + start, k - start - len(expected), text, expected))
    return commands


def mask_times(line):
    for pattern in TIMES:
        line = pattern.sub(lambda m: "<time>" + m.group(0)[m.group(0).index(" "):], line)
    return line


def significant_digits(token):
    return len(Decimal(token).as_tuple().digits)


def last_digit_unit(a, b):
    """One unit in the last significant digit of the pair: as many digits as the more precise one shows, and
    at least 2 (a %g number drops trailing zeros: "9e-05" may be 9.0e-05, but "1e-05" is not "2e-05")."""
    digits = max(significant_digits(a), significant_digits(b), 2)
    leading = max(Decimal(a).adjusted(), Decimal(b).adjusted())
    return Decimal(1).scaleb(leading - (digits - 1))


def is_integer(token):
    return not any(c in token for c in ".eE")


def numbers_agree(a, b):
    """The same text; both at rounding level, or both its reciprocal; else at most one unit in the last
    significant digit apart (last_digit_unit), unless both are plain integers (counts, ranks, lines)."""
    if a == b:
        return True
    x, y = Decimal(a), Decimal(b)
    if abs(x) <= ROUNDING_LEVEL and abs(y) <= ROUNDING_LEVEL:
        return True
    if abs(x) >= ABOVE_ROUNDING and abs(y) >= ABOVE_ROUNDING:
        return True
    if is_integer(a) and is_integer(b):
        return False
    return abs(x - y) <= last_digit_unit(a, b)


def lines_agree(expected, actual):
    expected, actual = mask_times(expected.rstrip()), mask_times(actual.rstrip())
    if expected == actual:
        return True
    e_numbers, a_numbers = NUMBER.findall(expected), NUMBER.findall(actual)
    e_text, a_text = NUMBER.split(expected), NUMBER.split(actual)
    if len(e_numbers) != len(a_numbers):
        return False
    differs = [e != a for e, a in zip(e_numbers, a_numbers)]
    if not all(numbers_agree(e, a) for e, a in zip(e_numbers, a_numbers)):
        return False
    for k, (e, a) in enumerate(zip(e_text, a_text)):
        next_to_changed = (k > 0 and differs[k - 1]) or (k < len(differs) and differs[k])
        if e != a and not (next_to_changed and e.split() == a.split()
                           and e[:1].isspace() == a[:1].isspace() and e[-1:].isspace() == a[-1:].isspace()):
            return False
    return True


def is_ellipsis(line):
    return line.strip() == "..."


def first_unmatched(expected, actual):
    """-1 when the expected lines (with `...`) match the actual ones, else the index of the first expected
    line no alignment gets past (len(expected) when the output goes on after the last one)."""
    n, m = len(expected), len(actual)
    # reach[i][j]: expected[:i] can match actual[:j]
    reach = [[False] * (m + 1) for _ in range(n + 1)]
    reach[0][0] = True
    furthest = 0
    for i in range(n + 1):
        for j in range(m + 1):
            if not reach[i][j]:
                continue
            furthest = max(furthest, i)
            if i == n:
                continue
            if is_ellipsis(expected[i]):
                for jj in range(j, m + 1):
                    reach[i + 1][jj] = True
            elif j < m and lines_agree(expected[i], actual[j]):
                reach[i + 1][j + 1] = True
    return -1 if reach[n][m] else furthest


def expected_line(command, index):
    """The Markdown line of expected line `index`: after the command's own (continued) lines."""
    return command.line + command.lines + index


def run(lowpair, command, cwd, display):
    try:
        argv = shlex.split(command.text, comments=True)
    except ValueError as error:
        raise ExampleError(f"{display}:{command.line}: {error}") from None
    if not argv or argv[0] != "lowpair":
        raise ExampleError(f"{display}:{command.line}: not a lowpair command")
    result = subprocess.run([lowpair] + argv[1:], cwd=cwd, stdin=subprocess.DEVNULL, capture_output=True,
                            timeout=COMMAND_TIMEOUT)
    output = (result.stdout + result.stderr).decode("utf-8", errors="replace")
    return result.returncode, output.splitlines()


def check_file(path, display, lowpair, root, totals):
    """Run every example of one Markdown file; returns the number of mismatches."""
    blocks = parse_blocks(display, path.read_text(encoding="utf-8").splitlines())
    if not blocks:
        return 0
    totals["files"] += 1
    failures = 0
    with tempfile.TemporaryDirectory(prefix="lowpair-docs-") as work:
        for name in LINKS:
            if (root / name).exists():
                os.symlink(root / name, Path(work) / name)
        for block in blocks:
            totals["blocks"] += 1
            if block.skip_reason:
                totals["skipped"].append(f"{display}:{block.line}: {block.skip_reason}")
                continue
            for command in block.commands:
                if " ... " in f" {command.text} ":
                    raise ExampleError(f"{display}:{command.line}: an elided command (` ... `): write it in "
                                       "full, or mark the block as not run")
                started = time.monotonic()
                status, actual = run(lowpair, command, work, display)
                seconds = time.monotonic() - started
                totals["commands"] += 1
                totals["slowest"] = max(totals["slowest"], (seconds, f"{display}:{command.line}"))
                unmatched = first_unmatched(command.expected, actual)
                if status >= 0 and unmatched < 0:
                    continue
                failures += 1
                print(f"MISMATCH {display}:{command.line}: $ {command.text}")
                if status < 0:
                    print(f"  killed by signal {-status}")
                elif unmatched < len(command.expected):
                    print(f"  exit status {status}; first expected line not matched: "
                          f"{display}:{expected_line(command, unmatched)}: {command.expected[unmatched]!r}")
                else:
                    print(f"  exit status {status}; the output goes on after the last expected line")
                sys.stdout.writelines(difflib.unified_diff(  # times masked: they are never the difference
                    [mask_times(line) + "\n" for line in command.expected],
                    [mask_times(line) + "\n" for line in actual],
                    fromfile=f"{display}:{command.line} (expected)", tofile="lowpair (actual)"))
                print()
    return failures


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--lowpair", required=True, help="the lowpair binary to run")
    parser.add_argument("--root", required=True, help="the source tree (README.md, docs/, models/, ...)")
    parser.add_argument("files", nargs="*", help="Markdown files (default: README.md and docs/*.md)")
    args = parser.parse_args()

    if os.environ.get("LOWPAIR_SANITIZE"):
        print("docs_examples: skipped: LOWPAIR_SANITIZE is set (the sanitizer build prints other "
              "rounding-level digits, and is slow)")
        return SKIP_EXIT
    root = Path(args.root).resolve()
    lowpair = str(Path(args.lowpair).resolve())
    if not os.access(lowpair, os.X_OK):
        print(f"docs_examples: error: --lowpair {args.lowpair}: not an executable file", file=sys.stderr)
        return 2
    files = [Path(f).resolve() for f in args.files]
    if not files:
        files = [root / "README.md"] + sorted((root / "docs").glob("*.md"))

    totals = {"scanned": len(files), "files": 0, "blocks": 0, "commands": 0, "skipped": [],
              "slowest": (0.0, "")}
    failures = 0
    started = time.monotonic()
    try:
        for path in files:
            display = os.path.relpath(path, root)
            failures += check_file(path, display, lowpair, root, totals)
    except (ExampleError, OSError, subprocess.TimeoutExpired) as error:
        print(f"docs_examples: error: {error}", file=sys.stderr)
        return 2
    for entry in totals["skipped"]:
        print(f"skipped (not run): {entry}")
    seconds, where = totals["slowest"]
    print(f"docs_examples: {totals['scanned']} files read, {totals['files']} with examples, "
          f"{totals['blocks']} blocks ({len(totals['skipped'])} not run), {totals['commands']} commands run; "
          f"{failures} mismatch(es); {time.monotonic() - started:.1f} s (slowest {where}, {seconds:.1f} s)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
