#!/usr/bin/env python3
"""docs/cli.md against the programs: every option a command's --help lists is in that command's
table in docs/cli.md, and every option the table lists is one the command takes (issue #27: the
reference kept in step with the code).

usage: check_cli_docs.py SOURCE_DIR BUILD_DIR
"""
import re
import subprocess
import sys
from pathlib import Path

source, build = Path(sys.argv[1]), Path(sys.argv[2])
programs = {
    "mocapd": build / "mocapd" / "mocapd",
    "mocap": build / "client" / "mocap",
    "mocap-load": build / "client" / "mocap-load",
    "mocap-eval": build / "eval" / "mocap-eval",
}
option = re.compile(r"(?<![\w-])(--[a-z][a-z0-9-]*)")

# Each heading that names a command (`mocapd tenant add-key`), with the options its tables list.
sections = {}
current = None
for line in (source / "docs" / "cli.md").read_text(encoding="utf-8").splitlines():
    heading = re.match(r"#+ `([a-z-]+(?: [a-z-]+)*)`\s*$", line)
    if heading:
        current = heading.group(1)
        sections[current] = set()
    elif line.startswith("#"):
        current = None
    elif current and re.match(r"\| `(-[a-z],)?--", line):
        sections[current].add(re.match(r"\| `(?:-[a-z],)?(--[a-z0-9-]+)", line).group(1))

problems, checked = [], 0
for command, documented in sections.items():
    words = command.split()
    program = programs.get(words[0])
    if program is None or not documented:
        continue
    if not program.exists():
        problems.append(f"{program} is not built")
        continue
    run = subprocess.run([str(program), *words[1:], "--help"], capture_output=True, text=True)
    if run.returncode != 0:
        problems.append(f"`{command} --help` failed ({run.returncode}): {run.stderr.strip()[:200]}")
        continue
    # Options are the first word of their --help line ("  -q,--quiet", "  --store TEXT").
    offered = set()
    for help_line in run.stdout.splitlines():
        first = help_line.strip().split(" ")[0]
        offered.update(option.findall(first))
    offered.discard("--help")
    checked += 1
    for missing in sorted(offered - documented):
        problems.append(f"`{command}`: {missing} is in --help but not in docs/cli.md")
    for extra in sorted(documented - offered):
        problems.append(f"`{command}`: docs/cli.md lists {extra}, which --help does not")

for problem in problems:
    print(problem)
print(f"checked {checked} commands' options against docs/cli.md: {len(problems)} differences")
sys.exit(1 if problems else 0)
