#!/usr/bin/env python3
"""Lines per function in C++ sources: a brace counter, no compiler needed.

Usage: scripts/function_lengths.py [--max N] FILE_OR_DIR...
Prints `lines file:line name` for every function (free, member, or defined in a class body),
longest first; lambdas count as part of the function they are written in. With --max N, exits
non-zero when any function is longer than N lines. A function's length runs from the line of
its name to its closing brace.
"""
import argparse
import signal
import pathlib
import re
import sys

CONTROL = re.compile(r"^(if|for|while|switch|catch|do|else|try|return)\b")
NON_FUNCTION = re.compile(r"\b(namespace|struct|class|enum|union)\b[^()]*$")


def strip(text):
    """Comments, string and character literals blanked, newlines kept (line numbers stay)."""
    out = []
    i, n = 0, len(text)
    while i < n:
        c = text[i]
        if text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
            i = j
        elif text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            out.append("\n" * text.count("\n", i, j))
            i = j
        elif text.startswith('R"', i):
            m = re.match(r'R"([^(]*)\(', text[i:])
            end = text.find(")" + m.group(1) + '"', i) if m else -1
            j = n if end < 0 else end + len(m.group(1)) + 2
            out.append('""' + "\n" * text.count("\n", i, j))
            i = j
        elif c in "\"'":
            j = i + 1
            while j < n and text[j] != c:
                j += 2 if text[j] == "\\" else 1
            out.append(c + c)
            i = j + 1
        else:
            out.append(c)
            i += 1
    return "".join(out)


def functions(path):
    text = strip(path.read_text())
    stack = []  # per open brace: (is_function, start_line, name)
    header_start = 0
    results = []
    in_function = 0
    for i, c in enumerate(text):
        if c == "{":
            header = text[header_start:i].strip()
            # A header spanning a template or attribute line keeps only the declaration.
            is_fn = False
            name = ""
            if not in_function and header and not CONTROL.match(header):
                flat = " ".join(header.split())
                if not NON_FUNCTION.search(flat.split("(")[0] + " ") and "(" in flat:
                    sig = flat.split("(")[0].split()
                    name = sig[-1] if sig else ""
                    # A constructor's initialiser list or a trailing const/noexcept/override.
                    if re.search(r"\)\s*(const|noexcept|override|final|mutable|->[^{]*|:[^{]*)*\s*$",
                                 flat) and name and not flat.startswith("="):
                        is_fn = not re.search(r"=\s*$", flat.split("(")[0])
            if is_fn:
                offset = header_start + (len(text[header_start:i]) - len(text[header_start:i].lstrip()))
                start_line = text.count("\n", 0, offset) + 1
                in_function += 1
            else:
                start_line = 0
            stack.append((is_fn, start_line, name))
            header_start = i + 1
        elif c == "}":
            if stack:
                is_fn, start_line, name = stack.pop()
                if is_fn:
                    in_function -= 1
                    end_line = text.count("\n", 0, i) + 1
                    results.append((end_line - start_line + 1, f"{path}:{start_line}", name))
            header_start = i + 1
        elif c == ";":
            header_start = i + 1
        elif c == "#" and (i == 0 or text[i - 1] == "\n"):
            # Preprocessor lines are not part of any header.
            j = text.find("\n", i)
            header_start = (len(text) if j < 0 else j) if not in_function else header_start
    return results


def main():
    signal.signal(signal.SIGPIPE, signal.SIG_DFL)  # `| head` ends the listing quietly
    p = argparse.ArgumentParser()
    p.add_argument("--max", type=int)
    p.add_argument("paths", nargs="+")
    a = p.parse_args()
    files = []
    for arg in a.paths:
        q = pathlib.Path(arg)
        files += sorted(q.rglob("*.[ch]pp")) if q.is_dir() else [q]
    rows = sorted((r for f in files for r in functions(f)), reverse=True)
    for lines, where, name in rows:
        print(f"{lines:5d} {where} {name}")
    if a.max is not None and rows and rows[0][0] > a.max:
        print(f"longest function {rows[0][0]} lines > {a.max}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
