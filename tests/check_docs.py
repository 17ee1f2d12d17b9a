#!/usr/bin/env python3
"""The docs' claims that a script can check against the code, checked.

  check_docs.py SOURCE_DIR BULLET_INCLUDE_DIR

- the README's code block is the code tests/test_readme_example.cpp runs (line for line, its
  "... add bodies ..." line aside);
- every field of btOpenCLSolverConfig has a row in docs/usage.md's config table, and no row
  names a field that is gone;
- every environment variable the library reads is in the README's variable table, and no row
  names one it does not read;
- every solver-mode flag of Bullet's btContactSolverInfo.h has a row in docs/usage.md;
- every btocl_bench scene is described in demos/bench/README.md, and every speed scene of
  scripts/benchmarks.sh exists;
- every repository path the README and docs/*.md quote in backticks exists.
Prints each mismatch and exits 1 if there is any.
"""
import glob
import os
import re
import sys

root, bullet_include = sys.argv[1], sys.argv[2]
problems = []


def read(rel):
    with open(os.path.join(root, rel)) as f:
        return f.read()


def table_first_cells(text, heading_first_cell):
    """The first cells (backticked names) of the Markdown table whose header starts with the given cell."""
    cells, inside = [], False
    for line in text.split("\n"):
        if line.startswith("| %s |" % heading_first_cell):
            inside = True
            continue
        if inside:
            if not line.startswith("|"):
                break
            cells.append(line.split("|")[1])
    return cells


def names_in_table(text, heading_first_cell, pattern=r"`(\w+)`"):
    found = set()
    for cell in table_first_cells(text, heading_first_cell):
        found.update(re.findall(pattern, cell))
    return found


def compare(in_code, in_doc, missing, extra):
    """Each name the code has and the doc lacks, and the reverse, as a problem."""
    problems.extend(missing % n for n in sorted(in_code - in_doc))
    problems.extend(extra % n for n in sorted(in_doc - in_code))


readme = read("README.md")
usage = read("docs/usage.md")

# The README's example against the test that runs it.
block = re.search(r"```cpp\n(.*?)```", readme, re.S).group(1)
test = read("tests/test_readme_example.cpp")
body = test[test.index("readmeExample() {"):]
position = 0
for line in block.split("\n"):
    line = line.strip()
    if not line or line.startswith("#include") or line.startswith("// ..."):
        continue
    found = body.find(line, position)
    if found < 0:
        problems.append("README code line not in tests/test_readme_example.cpp (in order): %s" % line)
    else:
        position = found + len(line)

# Config fields against docs/usage.md.
header = read("bullet_plugin/include/btOpenCLConstraintSolver.h")
config = re.search(r"struct btOpenCLSolverConfig \{(.*?)\n\};", header, re.S).group(1)
code_fields = set(re.findall(r"^\s+[\w:<>]+\s+(\w+)(?:\s*=[^;]*)?;", config, re.M))
compare(code_fields, names_in_table(usage, "field"),
        "btOpenCLSolverConfig::%s has no row in docs/usage.md's config table",
        "docs/usage.md's config table names %s, not a field of btOpenCLSolverConfig")

# Environment variables read by the library against the README's table.
read_vars = set()
for path in glob.glob(os.path.join(root, "bullet_plugin", "**", "*.cpp"), recursive=True):
    with open(path) as f:
        read_vars.update(re.findall(r'getenv\("(\w+)"\)', f.read()))
compare(read_vars, names_in_table(readme, "variable"),
        "the library reads %s; the README's variable table does not list it",
        "the README's variable table lists %s; the library does not read it")

# Bullet's solver-mode flags against docs/usage.md.
with open(os.path.join(bullet_include, "BulletDynamics", "ConstraintSolver", "btContactSolverInfo.h")) as f:
    flags = set(re.findall(r"^\s*(SOLVER_\w+)\s*=", f.read(), re.M))
compare(flags, names_in_table(usage, "flag", r"`(SOLVER_\w+)`"),
        "Bullet's %s has no row in docs/usage.md's solver-mode table", "docs/usage.md lists %s, not one of Bullet's flags")

# The bench's scenes against its README and the benchmark script.
scenes = re.findall(r'^\s+\{"([\w-]+)", "', read("demos/bench/Scenes.cpp"), re.M)
bench_readme = read("demos/bench/README.md")
for s in scenes:
    if "`%s`" % s not in bench_readme:
        problems.append("btocl_bench scene %s is not described in demos/bench/README.md" % s)
for s in re.findall(r'^\s+"([\w-]+) \d+ \d+"$', read("scripts/benchmarks.sh"), re.M):
    if s not in scenes:
        problems.append("scripts/benchmarks.sh runs scene %s, which btocl_bench does not have" % s)

# Paths quoted in backticks.
docs = ["README.md", "demos/bench/README.md"] + [os.path.relpath(p, root) for p in glob.glob(os.path.join(root, "docs", "*.md"))]
# A path is the repository's when it starts at one of its folders (or is a top-level file that
# the docs name with its folder-less name, such as CHANGELOG.md).
top = {"bullet_plugin", "kernels", "demos", "tests", "docs", "scripts", "reference", "scenes", "cmake", "examples",
       ".ci", "CHANGELOG.md", "README.md", "LICENSE", "CMakeLists.txt"}
for doc in docs:
    for path in set(re.findall(r"`([\w.-]+/[\w./-]*|[\w-]+\.(?:md|sh|py|txt))`", read(doc))):
        first = path.split("/")[0]
        placeholder = any(re.fullmatch(r"[A-Z]+", part) for part in path.split("/"))
        if first not in top or path.startswith("build") or "*" in path or placeholder:
            continue  # not a repository path (a build output, an install path, a pattern)
        if not os.path.exists(os.path.join(root, path.rstrip("/"))):
            problems.append("%s quotes %s, which does not exist" % (doc, path))

for p in problems:
    print("check_docs: " + p)
print("check_docs: %d problem(s); %d config fields, %d variables, %d solver-mode flags, %d scenes checked" % (
    len(problems), len(code_fields), len(read_vars), len(flags), len(scenes)))
sys.exit(1 if problems else 0)
