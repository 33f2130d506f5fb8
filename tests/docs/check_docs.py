#!/usr/bin/python3
"""Checks that the user documentation still matches the project.

  check_docs.py --incise PATH/TO/incise --root REPOSITORY [--keys-file FILE]

(a) Links: every relative link [text](path) and [text](path#anchor) (and reference definitions
    "[name]: path") in README.md, ARCHITECTURE.md, CHANGELOG.md and docs/*.md names an existing file or
    folder, relative to the page; an anchor names a heading of the target page (GitHub's slugs: lower case,
    punctuation dropped, spaces to hyphens, "-1", "-2" for repeats) or an explicit id/name in it. Links
    inside code (fenced blocks, `spans`) are not links and are skipped, as are URLs with a scheme.
(b) Commands: every command and subcommand `incise --help` lists (and recursively `incise hid --help` and
    the others) appears in docs/cli.md as `incise <command> [<subcommand>]` inside code (a `span` or a
    fenced block).
(c) Scenario keys: every key path `incise keys` prints (one per line, e.g. tissue.tets.max_volume_m3,
    pose_source.strokes[].length_m) appears in docs/scenarios.md inside a `span` or a fenced block, as the
    whole path (not as the start of a longer one). --keys-file FILE reads the list from FILE instead.

Every failure is printed as "file:line: what"; the exit code is 1 if there is any, 2 for bad arguments,
0 otherwise. Standard library only (Debian's /usr/bin/python3).
"""

import argparse
import bisect
import glob
import os
import re
import subprocess
import sys
import unicodedata

PAGES = ["README.md", "ARCHITECTURE.md", "CHANGELOG.md"]
FENCE = re.compile(r"^ {0,3}(`{3,}|~{3,})")
INLINE_LINK = re.compile(r"!?\[((?:[^\[\]]|\[[^\]]*\])*)\]\(\s*(<[^>]*>|[^)\s]+)(?:\s+\"[^\"]*\"|\s+'[^']*')?\s*\)")
REFERENCE_DEF = re.compile(r"^ {0,3}\[([^\]]+)\]:\s*(<[^>]*>|\S+)")
ATX_HEADING = re.compile(r"^ {0,3}(#{1,6})(?:[ \t]+(.*?))?(?:[ \t]+#+)?[ \t]*$")
SETEXT_UNDERLINE = re.compile(r"^ {0,3}(=+|-+)[ \t]*$")
HTML_ID = re.compile(r"<[a-zA-Z][^>]*?\s(?:id|name)\s*=\s*[\"']([^\"']+)[\"']")
SCHEME = re.compile(r"^[a-zA-Z][a-zA-Z0-9+.-]*:")


class Failures:
    def __init__(self):
        self.lines = []

    def add(self, path, line, what):
        self.lines.append(f"{path}:{line}: {what}")


def read_lines(path):
    with open(path, encoding="utf-8") as f:
        return f.read().split("\n")


def split_code(lines):
    """Yields (line number, text outside code, code spans on the line, inside a fenced block) per line."""
    fence = None
    for number, line in enumerate(lines, start=1):
        m = FENCE.match(line)
        if fence is None and m:
            fence = m.group(1)[0] * len(m.group(1))
            yield number, "", [], True
            continue
        if fence is not None:
            if m and m.group(1).startswith(fence) and line.strip().strip(fence[0]) == "":
                fence = None
            yield number, "", [line], True
            continue
        spans = []
        outside = []
        pos = 0
        for span in re.finditer(r"(`+)(.+?)(?<!`)\1(?!`)", line):
            outside.append(line[pos : span.start()])
            spans.append(span.group(2).strip())
            pos = span.end()
        outside.append(line[pos:])
        yield number, " ".join(outside), spans, False


def heading_text(raw):
    """The text GitHub renders for a heading's markdown: code spans, links and emphasis reduced to text."""
    def plain(part):
        part = re.sub(r"!?\[([^\]]*)\]\([^)]*\)", r"\1", part)
        part = re.sub(r"<[^>]+>", "", part)
        part = part.replace("*", "")
        return re.sub(r"(^|\s)_+|_+(\s|$)", r"\1\2", part)

    out, pos = [], 0
    for span in re.finditer(r"(`+)(.+?)\1", raw):  # code spans keep their text as it is
        out += [plain(raw[pos : span.start()]), span.group(2).strip()]
        pos = span.end()
    out.append(plain(raw[pos:]))
    return "".join(out).strip()


def slug(text):
    """GitHub's anchor for a heading text (github-slugger): lower case, every character that is not a
    letter, digit, mark, space, hyphen or underscore dropped, each space a hyphen."""
    out = []
    for ch in text.lower():
        category = unicodedata.category(ch)
        if ch in " -_" or category[0] in "LNM":
            out.append("-" if ch == " " else ch)
    return "".join(out)


def anchors(lines):
    """Every anchor a page offers: its headings' slugs (with GitHub's -1, -2 for repeats) and explicit ids."""
    seen = {}
    found = set()
    previous_text = None
    for number, outside, spans, in_code in split_code(lines):
        line = lines[number - 1]
        if in_code:
            previous_text = None
            continue
        for m in HTML_ID.finditer(line):
            found.add(m.group(1))
        heading = None
        atx = ATX_HEADING.match(line)
        if atx:
            heading = atx.group(2) or ""
        elif previous_text and SETEXT_UNDERLINE.match(line):
            heading = previous_text
        previous_text = line.strip() if line.strip() and not atx else None
        if heading is None:
            continue
        base = slug(heading_text(heading))
        count = seen.get(base, 0)
        seen[base] = count + 1
        found.add(base if count == 0 else f"{base}-{count}")
    return found


def links(path):
    """(line number, target) of every link in a page outside code: inline links and images, whose text may run
    over several lines (reported at the line of the target), and reference definitions."""
    found = []
    pieces, starts = [], []
    offset = 0
    for number, outside, spans, in_code in split_code(read_lines(path)):
        starts.append(offset)
        pieces.append(outside)
        offset += len(outside) + 1
        definition = REFERENCE_DEF.match(outside)
        if definition:
            found.append((number, definition.group(2)))
    for m in INLINE_LINK.finditer("\n".join(pieces)):
        found.append((bisect.bisect_right(starts, m.start(2)), m.group(2)))
    return sorted(found)


def check_target(root, page, number, target, anchor_cache, failures):
    path = os.path.join(root, page)
    file_part, _, anchor = target.partition("#")
    resolved = os.path.normpath(os.path.join(os.path.dirname(path), file_part)) if file_part else path
    if not os.path.exists(resolved):
        failures.add(page, number, f"link to {target}: {os.path.relpath(resolved, root)} does not exist")
    elif anchor and (os.path.isdir(resolved) or not resolved.endswith(".md")):
        failures.add(page, number, f"link to {target}: an anchor into a file that is not markdown")
    elif anchor:
        if resolved not in anchor_cache:
            anchor_cache[resolved] = anchors(read_lines(resolved))
        if anchor not in anchor_cache[resolved]:
            failures.add(page, number, f"link to {target}: no heading '#{anchor}' in {os.path.relpath(resolved, root)}")


def check_links(root, failures):
    pages = [p for p in PAGES if os.path.exists(os.path.join(root, p))]
    pages += sorted(os.path.relpath(p, root) for p in glob.glob(os.path.join(root, "docs", "*.md")))
    anchor_cache = {}
    checked = 0
    for page in pages:
        for number, target in links(os.path.join(root, page)):
            target = target[1:-1] if target.startswith("<") else target
            if SCHEME.match(target) or target.startswith("//"):
                continue
            checked += 1
            check_target(root, page, number, target, anchor_cache, failures)
    return len(pages), checked


def run(command):
    try:
        done = subprocess.run(command, capture_output=True, text=True, timeout=60)
    except OSError as e:
        return 127, "", str(e)
    except subprocess.TimeoutExpired:
        return 124, "", "timed out after 60 s"
    return done.returncode, done.stdout, done.stderr


def subcommands(help_text):
    """The names a CLI11 help text lists under "Subcommands:"."""
    names = []
    inside = False
    for line in help_text.split("\n"):
        if line.strip() == "Subcommands:":
            inside = True
            continue
        if inside:
            m = re.match(r"^  (\S+)(\s|$)", line)
            if m:
                names.append(m.group(1))
            elif line.strip() and not line.startswith(" "):
                inside = False
    return names


def commands(incise, failures, prefix=()):
    """Every command path under `incise PREFIX --help`, depth first."""
    code, out, err = run([incise, *prefix, "--help"])
    if code != 0:
        failures.add("docs/cli.md", 1, f"`{' '.join(['incise', *prefix, '--help'])}` failed (exit {code}): "
                                       f"{(err or out).strip()[:200]}")
        return []
    found = []
    for name in subcommands(out):
        path = (*prefix, name)
        found.append(path)
        found += commands(incise, failures, path)
    return found


def code_text(lines):
    return [(number, text) for number, outside, spans, in_code in split_code(lines) for text in spans]


def check_commands(root, incise, failures):
    cli = os.path.join(root, "docs", "cli.md")
    if not os.path.exists(cli):
        failures.add("docs/cli.md", 1, "docs/cli.md does not exist")
        return 0
    code = code_text(read_lines(cli))
    paths = commands(incise, failures)
    for path in paths:
        pattern = re.compile(r"(?<![\w-])incise\s+" + r"\s+".join(map(re.escape, path)) + r"(?![\w-])")
        if not any(pattern.search(text) for _, text in code):
            shown = "incise " + " ".join(path)
            parent = " ".join(["incise", *path[:-1], "--help"])
            failures.add("docs/cli.md", 1, f"`{shown}` (listed by `{parent}`) is not documented: "
                                           f"no `{shown}` in code")
    return len(paths)


def scenario_keys(incise, keys_file, failures):
    if keys_file:
        with open(keys_file, encoding="utf-8") as f:
            return [k.strip() for k in f if k.strip() and not k.startswith("#")]
    if "keys" not in subcommands(run([incise, "--help"])[1]):
        failures.add("docs/scenarios.md", 1, "incise keys: command not found (not in `incise --help`; "
                                             "--keys-file FILE checks a list of keys instead)")
        return None
    code, out, err = run([incise, "keys"])
    keys = [k.strip() for k in out.split("\n") if k.strip()]
    if code != 0 or not keys:
        failures.add("docs/scenarios.md", 1, f"`incise keys` failed (exit {code}, {len(keys)} keys): "
                                             f"{err.strip()[:200]}")
        return None
    return keys


def check_keys(root, incise, keys_file, failures):
    keys = scenario_keys(incise, keys_file, failures)
    if keys is None:
        return 0
    page = os.path.join(root, "docs", "scenarios.md")
    if not os.path.exists(page):
        failures.add("docs/scenarios.md", 1, "docs/scenarios.md does not exist")
        return len(keys)
    code = code_text(read_lines(page))
    source = keys_file or "incise keys"
    for key in keys:
        pattern = re.compile(r"(?<![\w.\]\[])" + re.escape(key) + r"(?![\w.\[])")
        if not any(pattern.search(text) for _, text in code):
            failures.add("docs/scenarios.md", 1, f"scenario key `{key}` (from {source}) is not documented")
    return len(keys)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--incise", required=True, help="the incise binary")
    parser.add_argument("--root", required=True, help="the repository's root")
    parser.add_argument("--keys-file", help="the scenario keys, one per line, instead of `incise keys`")
    args = parser.parse_args()
    root = os.path.abspath(args.root)
    if not os.path.isfile(os.path.join(root, "README.md")):
        print(f"check_docs: {root} has no README.md: not the repository's root", file=sys.stderr)
        return 2
    if not (os.path.isfile(args.incise) and os.access(args.incise, os.X_OK)):
        print(f"check_docs: {args.incise} is not an executable", file=sys.stderr)
        return 2
    if args.keys_file and not os.path.isfile(args.keys_file):
        print(f"check_docs: --keys-file {args.keys_file} does not exist", file=sys.stderr)
        return 2
    failures = Failures()
    pages, links = check_links(root, failures)
    command_count = check_commands(root, args.incise, failures)
    key_count = check_keys(root, args.incise, args.keys_file, failures)
    for line in failures.lines:
        print(line)
    summary = f"{pages} pages, {links} relative links, {command_count} commands, {key_count} scenario keys"
    if failures.lines:
        print(f"check_docs: {len(failures.lines)} failure(s) ({summary})")
        return 1
    print(f"check_docs: ok ({summary})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
