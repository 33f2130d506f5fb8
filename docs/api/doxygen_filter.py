#!/usr/bin/python3
"""Doxygen's input filter for incise's C++ headers (Doxyfile.in: FILTER_PATTERNS): their plain `//`
comments, which say what, shapes, units, threads, cost and failure, become the reference's text.

  - the opening comment block becomes the file's documentation (@file), verbatim;
  - a comment block directly above a declaration becomes its documentation (///);
  - a comment after a member or an enumerator on its line (and the comment lines that continue it, indented
    under it) becomes that member's (///<).
Text outside `code spans` is escaped so that Doxygen reads it as words, never as commands or HTML.
A file that already speaks Doxygen (it opens with /**) passes unchanged. Prints the filtered file.
  doxygen_filter.py HEADER
"""
import re
import sys

COMMENT = re.compile(r"^(\s*)//(?!/)\s?(.*)$")
TRAILING = re.compile(r"^(\s*[^/\s].*?[;,])(\s+)//(?!/)\s?(.*)$")
NOT_A_DECLARATION = re.compile(r"^\s*($|#|}|namespace\b|public:|private:|protected:|//)")


SPECIAL = re.compile(r"([\\@<>&#%$])")


def escape(text):
    """Doxygen's special characters escaped outside `code spans` (an unpaired backtick becomes a quote)."""
    parts = text.split("`")
    if len(parts) % 2 == 0:
        return SPECIAL.sub(r"\\\1", text.replace("`", "'"))
    return "`".join(SPECIAL.sub(r"\\\1", p) if i % 2 == 0 else p for i, p in enumerate(parts))


def filtered(lines):
    out = []
    i = 0
    # The opening comment block: the file's documentation, verbatim (it is laid out for a fixed-width font).
    while i < len(lines) and COMMENT.match(lines[i]):
        out.append(("/** @file\n@verbatim\n" if i == 0 else "") + COMMENT.match(lines[i]).group(2))
        i += 1
    if i > 0:
        out[-1] += "\n@endverbatim */"
    trailing_column = None  # the column of the last trailing comment, for its continuation lines
    while i < len(lines):
        line = lines[i]
        trailing = TRAILING.match(line)
        comment = COMMENT.match(line)
        if trailing and '"' not in trailing.group(1):
            trailing_column = len(trailing.group(1)) + len(trailing.group(2))
            out.append(f"{trailing.group(1)}{trailing.group(2)}///< {escape(trailing.group(3))}")
            i += 1
            continue
        if comment and trailing_column is not None and len(comment.group(1)) == trailing_column:
            out.append(f"{comment.group(1)}///< {escape(comment.group(2))}")
            i += 1
            continue
        trailing_column = None
        if comment:
            block_end = i
            while block_end < len(lines) and COMMENT.match(lines[block_end]):
                block_end += 1
            documents = block_end < len(lines) and not NOT_A_DECLARATION.match(lines[block_end])
            for k in range(i, block_end):
                m = COMMENT.match(lines[k])
                out.append(f"{m.group(1)}/// {escape(m.group(2))}" if documents else lines[k])
            i = block_end
            continue
        out.append(line)
        i += 1
    return out


def main(path):
    with open(path, encoding="utf-8") as f:
        text = f.read()
    if text.lstrip().startswith("/**"):
        sys.stdout.write(text)
        return
    sys.stdout.write("\n".join(filtered(text.split("\n"))))


if __name__ == "__main__":
    main(sys.argv[1])
