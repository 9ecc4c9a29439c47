#!/usr/bin/python3
"""Doxygen's input filter for include/ (Doxyfile.in: INPUT_FILTER): the headers' own comments
become documentation without changing their style.

- C++ (`tricell/*.hpp`): each header is a Doxygen group named after its path, and what the
  header declares in namespace tricell joins it. The site's C++ page shows one group per header
  (after the header's own opening paragraph), so no namespace is documented twice.
  Declarations are already documented with `///` and `///<`.
- C (`tricell.h`, whose comments are plain C99 `/* */`): the opening block describes the file,
  a comment that starts a line documents the declaration after it, and one after code on a
  line documents that code's member or enumerator; rulers (`/* ---- Box ---- */`) stay plain.

usage: doxygen_filter.py HEADER   (prints the filtered header)
"""
import re
import sys


def group_name(path):
    """tricell/box.hpp -> tricell_box_hpp, the group of a header."""
    relative = path[path.rindex("tricell/"):] if "tricell/" in path else path
    return re.sub(r"\W", "_", relative), relative


def cpp_groups(lines, path):
    name, title = group_name(path)
    out = ["/** \\defgroup %s %s */" % (name, title)]
    open_group = "/** \\addtogroup %s\n \\{ */" % name
    in_member_definition = False
    for line in lines:
        # A class member defined outside its class (`inline T Box::wrap(...) {`) belongs to the
        # class only: the group pauses until its body's closing brace.
        if re.match(r"^\}\s*// namespace tricell\b", line) or OUT_OF_CLASS.match(line):
            out.append("/** \\} */")
            in_member_definition = bool(OUT_OF_CLASS.match(line))
        out.append(line)
        if re.match(r"^namespace tricell(::\w+)*\s*\{", line) or \
                (in_member_definition and line == "}"):
            out.append(open_group)
            in_member_definition = False
    return out


OUT_OF_CLASS = re.compile(r"^(inline |template)[^(;]*\b[A-Z]\w*::~?\w+\(")


RULER = re.compile(r"^\s*/\*\s*-{3,}")
LEADING = re.compile(r"^(\s*)/\*(?![*!])")
TRAILING = re.compile(r"^(\s*[^\s/].*?)/\*(?![*!<])")


def c_comments(lines):
    out = []
    in_comment = False
    for number, line in enumerate(lines):
        if not in_comment and not RULER.match(line):
            if number == 0 and line.startswith("/*"):
                line = "/** \\file\n" + line[2:].lstrip()
            elif LEADING.match(line):
                line = LEADING.sub(r"\1/**", line, count=1)
            elif TRAILING.match(line):
                line = TRAILING.sub(r"\1/**<", line, count=1)
        # Whether a comment stays open past this line.
        opened, closed = line.rfind("/*"), line.rfind("*/")
        in_comment = closed < 0 if in_comment else opened > closed
        out.append(line)
    return out


def main():
    path = sys.argv[1]
    with open(path, encoding="utf-8") as f:
        lines = f.read().split("\n")
    lines = c_comments(lines) if path.endswith(".h") else cpp_groups(lines, path)
    sys.stdout.write("\n".join(lines))


if __name__ == "__main__":
    main()
