#!/usr/bin/env python3
"""Every `vitrum run` command the documents show, run as written from the repository root (issue 28: a
documented command that fails is a defect). Each is reduced so that it takes seconds: --stop-after 1, its own
--out, no maps, and, unless it cuts its sample from another packing or restarts, a smaller fresh packing
(the command's own keys, paths and units are what is checked). `--help` commands run as they are. Commands with
placeholders (SCENE, NAME, OUT, RUN_DIR, [options], ...) are not runnable and are listed as skipped, as are the
calibration sweeps (minutes to hours each; their reduced forms are tests of their own) and commands that
rewrite committed files. A `--restart` continues the reduced run of the same documented --out.

usage: readme_commands.py VITRUM REPO_ROOT   (exit 1 if any command fails; prints each with its result)
"""
import glob
import os
import re
import shlex
import subprocess
import sys
import tempfile

DOCUMENTS = ["README.md", "docs/*.md", "examples/README.md", "examples/*/README.md", "bench/README.md"]
PLACEHOLDER = re.compile(r"\b(SCENE|NAME|OUT|RUN_DIR|DIR|FILE)\b|\[--|\.\.\.|\|")


def commands(root):
    found = []
    for pattern in DOCUMENTS:
        for path in sorted(glob.glob(os.path.join(root, pattern))):
            text = open(path, encoding="utf-8").read()
            # Code spans and code-block lines that start a vitrum command.
            for match in re.finditer(r"(?:`|^)\s*(build/vitrum [^`\n]*)", text, re.M):
                command = match.group(1).split(" && ")[0].split("  #")[0].strip().rstrip("\\").strip()
                found.append((os.path.relpath(path, root), command))
    unique = []
    for item in found:
        if item[1] not in [c for _, c in unique]:
            unique.append(item)
    return unique


def main():
    vitrum, root = sys.argv[1], sys.argv[2]
    failed, ran, skipped = [], 0, []
    outs = {}  # a documented --out -> the reduced run's own directory
    with tempfile.TemporaryDirectory(prefix="vitrum-readme-") as tmp:
        for number, (document, command) in enumerate(commands(root)):
            words = shlex.split(command)
            restart_of = None
            if "--restart" in words and "--out" in words:
                # A documented stop-and-continue pair: continue the reduced run of the same --out.
                given = words[words.index("--out") + 1]
                restart_of = outs.get(given)
            if words[1] != "run" or ("--restart" in words and not restart_of) or PLACEHOLDER.search(command):
                if words[1] != "run" and "--help" in words:
                    pass  # a help command runs as it is
                else:
                    skipped.append((document, command))
                    continue
            words[0] = vitrum
            if words[1] == "run" and "--help" not in words:
                out = os.path.join(tmp, f"run{number}")
                words = [w for w in words]
                if "--out" in words:
                    outs[words[words.index("--out") + 1]] = out
                if restart_of:
                    out = restart_of
                    i = words.index("--restart")
                    words[i + 1] = os.path.join(out, "state.h5")
                for option in ("--out", "--stop-after"):
                    if option in words:
                        i = words.index(option)
                        del words[i:i + 2]
                words += ["--out", out, "--stop-after", "1", "--quiet", "--set", "output.maps=0"]
                if "cut_from" not in command:
                    words += ["--set", "sample.particles=3000", "--set", 'sample.file=""']
            result = subprocess.run(words, cwd=root, capture_output=True, text=True, timeout=600)
            ran += 1
            status = "ok" if result.returncode == 0 else f"FAILED (exit {result.returncode})"
            print(f"{status}: {document}: {command}")
            if result.returncode != 0:
                failed.append(command)
                print("   " + (result.stderr or result.stdout).strip().replace("\n", "\n   "))
    for document, command in skipped:
        print(f"skipped (not runnable as written): {document}: {command}")
    print(f"{ran} documented commands run, {len(failed)} failed, {len(skipped)} skipped")
    return 1 if failed or ran == 0 else 0


if __name__ == "__main__":
    sys.exit(main())
