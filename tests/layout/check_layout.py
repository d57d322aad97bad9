#!/usr/bin/env python3
"""The shape rules of the source tree, checked on every build of the tests.

- service/ has no file over 600 lines and no function over 60 lines; core/ and api/ no function
  over 80 lines (long functions hide the steps a reader needs to see; the limits are the brief's);
- service/ names no JSON library type (JSON lives in api/; service decides on typed results);
- no server file includes a header of the command-line tools (service/cli/);
- no comment names an issue or a review (comments say why, the history is in git);
- no test file (tests/test_*.cpp) opens an anonymous namespace: the test drivers compile as a
  unity build, which merges those of its files, so each file keeps its helpers in a namespace
  named after it (test_plan_cache.cpp: `namespace test_plan_cache`).

Problems listed in tests/layout/known_problems.txt are reported but do not fail the check until
they are fixed; an entry that no longer occurs fails it, so the list only shrinks.

Functions are found by a small lexer (comments and literals removed, braces matched): a brace at
namespace or class scope whose preceding declaration has a parameter list opens a function body;
lambdas and local classes count as lines of the function that holds them.

    python3 tests/layout/check_layout.py [repository root]
"""

import pathlib
import re
import sys

ROOT = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else pathlib.Path(__file__).parents[2])
SOURCES = (".cpp", ".hpp", ".h")
FUNCTION_LIMIT = {"service": 60, "core": 80, "api": 80}
FILE_LIMIT = {"service": 600}
HISTORY = re.compile(r"\b[Ii]ssue \d+|\b[Hh]ostile review|\breview(ed)? (found|said)")


def strip(text):
    """`text` with comments, preprocessor lines, string and character literals blanked (newlines
    kept)."""
    text = re.sub(r"(?m)^[ \t]*#(?:[^\n]*\\\n)*[^\n]*", lambda m: "\n" * m.group(0).count("\n"), text)
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
        elif text.startswith('R"', i) and (i == 0 or not (text[i - 1].isalnum() or text[i - 1] == "_")):
            m = re.match(r'R"([^(]*)\(', text[i:])
            end = text.find(")" + m.group(1) + '"', i) if m else -1
            j = n if end < 0 else end + len(m.group(1)) + 2
            out.append('""' + "\n" * text.count("\n", i, j))
            i = j
        elif c in "\"'":
            j = i + 1
            while j < n and text[j] != c and text[j] != "\n":
                j += 2 if text[j] == "\\" else 1
            out.append(c + c)
            i = j + 1
        else:
            out.append(c)
            i += 1
    return "".join(out)


def functions(text):
    """(name, first line, line count) of every function body at namespace or class scope."""
    code = strip(text)
    found = []
    stack = []  # per open brace: True when it is (inside) a function body
    start = 0  # where the declaration before the next brace begins
    for i, c in enumerate(code):
        if c in ";":
            start = i + 1
        elif c == "{":
            inside = bool(stack) and stack[-1]
            head = code[start:i]
            is_function = False
            if not inside:
                flat = re.sub(r"\s+", " ", head).strip()
                depth, assign = 0, False
                for ch in flat:
                    depth += ch == "("
                    depth -= ch == ")"
                    if ch == "=" and depth == 0:
                        assign = True
                opener = re.match(r"(template ?<.*> ?)?(namespace|class|struct|enum|union|extern)\b", flat)
                is_function = "(" in flat and not assign and not opener
                if is_function:
                    name = re.findall(r"([~\w:]+|operator\S+) ?\(", flat)
                    found.append([name[0] if name else flat[:40], code.count("\n", 0, i) + 1, i])
            stack.append(inside or is_function)
            start = i + 1
        elif c == "}":
            was_function = stack.pop() if stack else False
            if was_function and not (stack and stack[-1]):
                for f in reversed(found):
                    if len(f) == 3:
                        f.append(code.count("\n", 0, i) + 1 - f[1] + 1)
                        break
            start = i + 1
    return [(f[0], f[1], f[3]) for f in found if len(f) == 4]


def self_check():
    """The lexer on a known snippet, so that a broken lexer cannot pass the tree silently."""
    body = "\n".join(["  x += 1; // }"] * 58)
    snippet = (
        'namespace a {\nconstexpr int k[] = {1, 2};\nstruct S {\n  int f() const {\n    return 1;\n  }\n};\n'
        'int g(int x = 2) {\n  auto l = [&] {\n    return "}";\n  };\n' + body + '\n}\n}  // namespace a\n')
    got = [(name, count) for name, _, count in functions(snippet)]
    want = [("f", 3), ("g", 63)]
    if got != want:
        sys.exit(f"check_layout's lexer is broken: found {got}, expected {want}")


def main():
    self_check()
    problems, details = [], []
    for top in ("core", "api", "service"):
        for path in sorted((ROOT / top).rglob("*")):
            if path.suffix not in SOURCES or "build" in path.parts:
                continue
            rel = path.relative_to(ROOT)
            text = path.read_text(encoding="utf-8")
            lines = text.count("\n")
            if top in FILE_LIMIT and lines > FILE_LIMIT[top]:
                problems.append(f"{rel}: over {FILE_LIMIT[top]} lines")
                details.append(f"{rel}: {lines} lines")
            for name, line, count in functions(text):
                if count > FUNCTION_LIMIT[top]:
                    problems.append(f"{rel}: {name} is over {FUNCTION_LIMIT[top]} lines")
                    details.append(f"{rel}:{line}: {name} has {count} lines")
            for number, line_text in enumerate(text.splitlines(), 1):
                if "//" in line_text and HISTORY.search(line_text[line_text.index("//"):]):
                    problems.append(f"{rel}: a comment names an issue or a review")
                    details.append(f"{rel}:{number}: {line_text.strip()[:80]}")
            if top == "service":
                code = strip(text)
                # nlohmann's types by their name or by the usual alias `json` (a member
                # `x.json` of an api struct is text, not the type).
                if ("nlohmann" in code or re.search(r"(?<![.>\w])json\b", code)
                        or re.search(r"#include\s*<nlohmann/", text)):
                    problems.append(f"{rel}: uses nlohmann/json (JSON lives in api/)")
                if "cli" not in rel.parts and re.search(r'#include\s*"(\.\./)?cli/', text):
                    problems.append(f"{rel}: a server file includes a header of the CLI")
    for path in sorted((ROOT / "tests").glob("test_*.cpp")):
        for number, line_text in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
            if re.match(r"\s*namespace\s*\{", line_text):
                rel = path.relative_to(ROOT)
                problems.append(f"{rel}: an anonymous namespace (name it {path.stem})")
                details.append(f"{rel}:{number}: {line_text.strip()}")
    known_file = pathlib.Path(__file__).with_name("known_problems.txt")
    known = {line.strip() for line in known_file.read_text(encoding="utf-8").splitlines()
             if line.strip() and not line.startswith("#")} if known_file.exists() else set()
    new = [p for p in problems if p not in known]
    fixed = sorted(known - set(problems))
    problems = sorted(set(problems))
    for problem in problems:
        print(("known: " if problem in known else "NEW: ") + problem)
    for detail in details:
        print("  " + detail)
    for problem in fixed:
        print("FIXED (remove it from known_problems.txt): " + problem)
    print(f"{len(problems)} problem(s), {len(new)} new, {len(fixed)} fixed")
    return 1 if new or fixed else 0


if __name__ == "__main__":
    sys.exit(main())
