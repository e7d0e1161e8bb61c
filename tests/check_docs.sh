#!/usr/bin/env bash
# The README and the guides in docs/ link to each other by relative paths and heading anchors; a
# renamed file or heading otherwise leaves a dead link that no test notices. Checks every relative
# link and image in README.md, docs/**/*.md (subfolders such as docs/devices/ too),
# client/README.md and viewer/README.md: the file exists, and a #fragment names a heading of that
# file (anchors as GitHub makes them: lower case, punctuation dropped, spaces to hyphens, -1, -2...
# for repeats).
#   usage: tests/check_docs.sh SOURCE_DIR
set -euo pipefail
cd "$1"
shopt -s globstar
python3 - README.md docs/**/*.md client/README.md viewer/README.md <<'EOF'
import os, re, sys

def anchors(path):
    found, seen, fenced = set(), {}, False
    for line in open(path, encoding="utf-8"):
        if line.startswith("```"):
            fenced = not fenced
        if fenced or not re.match(r"#{1,6} ", line):
            continue
        text = re.sub(r"^#+ ", "", line.strip())
        text = re.sub(r"\[([^\]]*)\]\([^)]*\)", r"\1", text)  # a link in a heading keeps its text
        slug = re.sub(r"[^\w\- ]", "", text.lower()).replace(" ", "-")
        n = seen.get(slug, 0)
        seen[slug] = n + 1
        found.add(slug if n == 0 else f"{slug}-{n}")
    return found

failures, checked = [], 0
for doc in sys.argv[1:]:
    text = open(doc, encoding="utf-8").read()
    text = re.sub(r"```.*?```", "", text, flags=re.S)  # links in code blocks are not links
    for target in re.findall(r"\]\(([^)\s]+)\)", text):
        if re.match(r"[a-z]+:", target):
            continue  # http:, https:, mailto:
        checked += 1
        path, _, fragment = target.partition("#")
        file = os.path.normpath(os.path.join(os.path.dirname(doc), path)) if path else doc
        if not os.path.exists(file):
            failures.append(f"{doc}: {target}: no file {file}")
        elif fragment and (not file.endswith(".md") or fragment not in anchors(file)):
            failures.append(f"{doc}: {target}: no heading #{fragment} in {file}")
print("\n".join(failures + [f"checked {checked} links"]))
sys.exit(1 if failures or checked == 0 else 0)
EOF
