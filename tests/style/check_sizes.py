#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Size limits of issue 16: no file under lib/ above 600 lines, no function above 80 lines.

Run as `check_sizes.py [repo]`; exit 1 when a file or function over the limit is found, listing
each. REPORT_ONLY (files listed but not failing) and KNOWN_FUNCTIONS ((file, function) pairs
reported only) are empty: every file and function under lib/ meets the limits (issue 16). Add an
entry only with a reason and an issue that removes it again.

A function is a brace block opened after a `)` (optionally followed by const, noexcept,
override, a trailing return type or a constructor initializer list) at namespace or class
scope; its length runs from the first line of its signature to its closing brace. Lambdas and
local classes count toward the function that holds them.
"""

import re
import sys
from pathlib import Path

MAX_FILE = 600
MAX_FUNCTION = 80
REPORT_ONLY = ()
KNOWN_FUNCTIONS = set()
SOURCES = ("*.cpp", "*.hpp", "*.h", "*.cc")


def strip(text):
    """Blanks comments, string and char literals (keeping newlines) so braces can be counted."""
    out, i, n = [], 0, len(text)
    while i < n:
        c = text[i]
        if text.startswith("//", i):
            j = text.find("\n", i)
            i = n if j < 0 else j
            continue
        if text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
            continue
        m = re.match(r'R"([^(]*)\(', text[i:i + 20]) if c == "R" and (i == 0 or not (
            text[i - 1].isalnum() or text[i - 1] == "_")) else None
        if m:
            end = text.find(")" + m.group(1) + '"', i)
            end = n if end < 0 else end + len(m.group(1)) + 2
            out.append(re.sub(r"[^\n]", " ", text[i:end]))
            i = end
            continue
        if c in "\"'":
            if c == "'" and i > 0 and text[i - 1].isalnum() and i + 1 < n and text[i + 1].isalnum():
                out.append(" ")  # digit separator 1'000
                i += 1
                continue
            j = i + 1
            while j < n and text[j] != c:
                j += 2 if text[j] == "\\" else 1
            out.append(c + " " * max(0, min(j, n) - i - 1) + (c if j < n else ""))
            i = j + 1
            continue
        out.append(c)
        i += 1
    return "".join(out)


SCOPE = re.compile(r"\b(namespace|class|struct|union|enum)\b[^;{}()]*$")
FUNC_TAIL = re.compile(r"\)\s*(const\b|noexcept\b|override\b|final\b|mutable\b|&|->[^{;]*|"
                       r":[^;{]*|\s)*$")
CONTROL = re.compile(r"\b(if|for|while|switch|catch)\s*\(")


def functions(text):
    """(name, first line, line count) of each function defined at namespace or class scope."""
    s = strip(text)
    result = []
    stack = []  # one entry per open brace: "scope", "function" or "block"
    start = 0  # index just after the last ; { } at the current level
    for i, c in enumerate(s):
        if c == "{":
            head = s[start:i]
            kind = "block"
            if all(k[0] == "scope" for k in stack):
                if SCOPE.search(head) or re.search(r"\bextern\s+\"", head):
                    kind = "scope"
                elif FUNC_TAIL.search(head) and not CONTROL.match(head.strip()) \
                        and not re.search(r"=\s*$", head.strip()):
                    kind = "function"
                    sig = head.strip()
                    first = s.count("\n", 0, start + (len(head) - len(head.lstrip())))
                    name = re.findall(r"([~\w:]+)\s*\(", sig)
                    stack.append(("function", first, name[0] if name else sig[:40]))
                    start = i + 1
                    continue
            stack.append((kind, None, None))
            start = i + 1
        elif c == "}":
            if stack:
                kind, first, name = stack.pop()
                if kind == "function":
                    last = s.count("\n", 0, i)
                    result.append((name, first + 1, last - first + 1))
            start = i + 1
        elif c == ";" and all(k[0] == "scope" for k in stack):
            start = i + 1
    return result


def main():
    repo = Path(sys.argv[1] if len(sys.argv) > 1 else Path(__file__).resolve().parents[2])
    failures, reported = [], []
    files = sorted(p for pat in SOURCES for p in (repo / "lib").rglob(pat))
    for path in files:
        rel = path.relative_to(repo).as_posix()
        text = path.read_text(errors="replace")
        out = failures
        if rel.startswith(REPORT_ONLY):
            out = reported
        lines = text.count("\n")
        if lines > MAX_FILE:
            out.append(f"{rel}: {lines} lines (limit {MAX_FILE})")
        for name, first, count in functions(text):
            if count > MAX_FUNCTION:
                (reported if (rel, name) in KNOWN_FUNCTIONS else out).append(f"{rel}:{first}: function {name} is {count} lines "
                           f"(limit {MAX_FUNCTION})")
    for r in reported:
        print(f"report only (issue 16, not split yet): {r}")
    for f in failures:
        print(f"FAIL {f}")
    print(f"{len(files)} files checked: {len(failures)} over the limits, "
          f"{len(reported)} reported only")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
