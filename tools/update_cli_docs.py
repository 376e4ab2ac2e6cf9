#!/usr/bin/env python3
"""docs/cli.md's help blocks and docs/config.md's key table from the binary: each fenced block of
cli.md holding "Usage: aamap ..." lines is the `--help` output of those commands, copied verbatim,
one after the other; config.md's table between <!-- keys --> and <!-- /keys --> is
`aamap run --list-keys` (every schema key's type, range, default and meaning, from its declaration).

    python3 tools/update_cli_docs.py [--aamap build/release/aamap]          # rewrites docs/cli.md
    python3 tools/update_cli_docs.py --check [--aamap build/release/aamap]  # exit 1 if stale

`cmake --build --preset release --target cli-docs` runs the first; the test `docs.cli_help` the
second, so the page cannot drift from the options the binary takes. The prose around the blocks
is written by hand; a command whose help has no block is an error, so a new subcommand gets one.
"""
import argparse
import difflib
import os
import re
import subprocess
import sys

COMMANDS = ["", "run", "report", "snapshot", "view", "compare", "diff"]


def help_text(aamap, command):
    args = [aamap] + ([command] if command else []) + ["--help"]
    out = subprocess.run(args, check=True, capture_output=True, text=True).stdout
    return out.rstrip("\n").split("\n")


def usage_command(line):
    """"run" for "Usage: aamap run [OPTIONS] ...", "" for the top level; None for other lines."""
    m = re.match(r"Usage: aamap( [a-z]+)? ", line)
    if not m:
        return None
    return (m.group(1) or "").strip()


def rewrite(lines, helps):
    """The page with every help block replaced; the commands whose block was found."""
    out, found, i = [], set(), 0
    while i < len(lines):
        if lines[i].startswith("```"):
            end = i + 1
            while end < len(lines) and not lines[end].startswith("```"):
                end += 1
            body = lines[i + 1:end]
            commands = [c for c in (usage_command(l) for l in body) if c is not None]
            if commands and all(c in helps for c in commands):
                # One block may hold several commands' help, one after the other.
                out.append(lines[i])
                for k, command in enumerate(commands):
                    found.add(command)
                    out += ([""] if k else []) + helps[command]
                out.append(lines[end] if end < len(lines) else "```")
            else:
                out += lines[i:end + 1]
            i = end + 1
        else:
            out.append(lines[i])
            i += 1
    return out, found


def rewrite_keys(lines, table):
    """config.md with the lines between the keys markers replaced by `table` (a list of lines)."""
    start, end = lines.index("<!-- keys -->"), lines.index("<!-- /keys -->")
    return lines[:start + 1] + table + lines[end:]


def write_or_check(path, lines, new, check, source):
    """0 when `path` is current (or was rewritten), 1 when --check finds it stale."""
    if new == lines:
        return 0
    if check:
        sys.stdout.writelines(difflib.unified_diff([l + "\n" for l in lines], [l + "\n" for l in new], path, source))
        print(f"{path} is stale: run `cmake --build --preset release --target cli-docs`", file=sys.stderr)
        return 1
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        f.write("\n".join(new))
    os.replace(tmp, path)
    print(f"{path}: rewritten from {source}")
    return 0


def main():
    repo = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--aamap", default=os.path.join(repo, "build", "release", "aamap"))
    ap.add_argument("--doc", default=os.path.join(repo, "docs", "cli.md"))
    ap.add_argument("--config-doc", default=os.path.join(repo, "docs", "config.md"))
    ap.add_argument("--check", action="store_true", help="compare only; exit 1 when the page is stale")
    args = ap.parse_args()
    helps = {c: help_text(args.aamap, c) for c in COMMANDS}
    with open(args.doc) as f:
        lines = f.read().split("\n")
    new, found = rewrite(lines, helps)
    missing = [c or "(top level)" for c in COMMANDS if c not in found]
    if missing:
        sys.exit(f"{args.doc}: no help block (a fence holding 'Usage: aamap ...') for {', '.join(missing)}")
    status = write_or_check(args.doc, lines, new, args.check, "aamap --help")
    keys = subprocess.run([args.aamap, "run", "--list-keys"], check=True, capture_output=True, text=True).stdout
    with open(args.config_doc) as f:
        config = f.read().split("\n")
    status |= write_or_check(args.config_doc, config, rewrite_keys(config, keys.rstrip("\n").split("\n")), args.check,
                             "aamap run --list-keys")
    return status

if __name__ == "__main__":
    sys.exit(main())
