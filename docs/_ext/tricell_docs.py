"""The site's generated parts, expanded when Sphinx reads a page (the `source-read` event):

- a fenced block `{tricell-python-modules}` becomes one section per module named in it, one
  name a line, each documented by autodoc from the built package's docstrings;
- a fenced block `{tricell-cpp-headers}` becomes one section per header named in it (paths
  under include/): the prose paragraph atop the header, then what it declares, from Doxygen's
  XML through breathe (docs/doxygen_filter.py makes each header a group); every public header
  must be named;
- a fenced block `{tricell-cli-help}` becomes the built command's `--help`, then each command's,
  one section each. The command is $TRICELL_CLI, which CMake sets to the target's file, and the
  commands are those its `--help` lists, so a new command appears without editing the page.

A block left unexpanded would be an unknown directive, which the warnings-as-errors build
refuses. The docstrings and header comments are plain text (see `paragraphs`): they are shown
as written, never read as markup.
"""
import glob
import os
import re
import subprocess
import xml.etree.ElementTree as ElementTree

BLOCK = re.compile(r"^```\{(tricell-[a-z-]+)\}\n(.*?)^```\n", re.M | re.S)
ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def paragraphs(lines):
    """Plain text as (preformatted, lines) paragraphs: blank lines separate them, and a
    paragraph with a line indented beyond its first (an example, a table, a continued
    signature) is preformatted, the others are prose to be reflowed."""
    found, current = [], []
    for line in lines + [""]:
        if line.strip():
            current.append(line.rstrip())
            continue
        if current:
            first = len(current[0]) - len(current[0].lstrip())
            indented = any(len(line) - len(line.lstrip()) > first for line in current[1:]) or first
            found.append((bool(indented), current))
        current = []
    return found


def python_modules(body):
    sections = []
    for name in body.split():
        sections.append(f"## `{name}`\n\n```{{eval-rst}}\n.. automodule:: {name}\n"
                        f"   :members:\n   :undoc-members:\n```\n")
    return "\n".join(sections)


# Any ASCII punctuation may be escaped in Markdown; escaped, none of it is taken for markup.
MARKDOWN_PUNCTUATION = re.compile(r"([!-/:-@\[-`{-~])")


def header_paragraph(path):
    """The `//` lines atop a header, as Markdown."""
    lines = []
    with open(path, encoding="utf-8") as f:
        for line in f:
            if not line.startswith("//"):
                break
            lines.append(re.sub(r"^// ?", "", line.rstrip("\n")))
    out = []
    for preformatted, text in paragraphs(lines):
        if preformatted:
            out.append("```text\n" + "\n".join(text) + "\n```\n")
        else:
            out.append("\n".join(MARKDOWN_PUNCTUATION.sub(r"\\\1", line.strip())
                                 for line in text) + "\n")
    return "\n".join(out)


def cpp_headers(body):
    """One section per header named in the block (paths under include/), each the Doxygen group
    docs/doxygen_filter.py makes of it; a public header missing from the block is an error."""
    listed = body.split()
    include = os.path.join(ROOT, "include")
    present = sorted(os.path.relpath(os.path.join(folder, name), include)
                     for folder, _, names in os.walk(os.path.join(include, "tricell"))
                     for name in names if name.endswith(".hpp"))
    missing = [header for header in present if header not in listed]
    if missing:
        raise RuntimeError("docs/api/cpp.md lists no section for " + ", ".join(missing))
    sections = []
    for header in listed:
        group = re.sub(r"\W", "_", header)
        sections.append(f"## `{header}`\n\n{header_paragraph(os.path.join(include, header))}\n"
                        f"```{{doxygengroup}} {group}\n:content-only:\n:members:\n"
                        f":undoc-members:\n```\n")
    return "\n".join(sections)


def run_cli(*args):
    command = os.environ.get("TRICELL_CLI")
    if not command or not os.access(command, os.X_OK):
        raise RuntimeError(f"TRICELL_CLI names no built tricell command (got {command!r}); "
                           "build the site with the `docs` target of CMake")
    out = subprocess.run([command, *args], capture_output=True, text=True, check=True)
    return out.stdout.rstrip("\n")


def fence(text):
    return "```text\n" + text + "\n```\n"


def cli_help(_body):
    overview = run_cli("--help")
    commands = []
    listing = overview.split("Commands:\n", 1)[1].split("\n\n", 1)[0]
    for line in listing.splitlines():
        match = re.match(r"^  (\w[\w-]*) ", line)
        if match and match.group(1) not in commands:
            commands.append(match.group(1))
    if not commands:
        raise RuntimeError("tricell --help lists no commands under 'Commands:'")
    parts = ["## `tricell --help`\n", fence(overview)]
    for name in commands:
        parts += [f"## `tricell {name} --help`\n", fence(run_cli(name, "--help"))]
    return "\n".join(parts)


EXPANSIONS = {"tricell-python-modules": python_modules, "tricell-cpp-headers": cpp_headers,
              "tricell-cli-help": cli_help}


def expand(_app, _docname, source):
    source[0] = BLOCK.sub(lambda m: EXPANSIONS[m.group(1)](m.group(2)), source[0])


def qualify_group_members(app):
    """Breathe names a function, enum, typedef or variable shown through a group without its
    namespace (breathe 4.34 takes the qualification from the enclosing class or namespace, and a
    group is neither), so `compute_neighbors(const Box&)` would be declared global and `Box` in
    it would resolve to nothing. This gives such a member the namespace of its qualified name in
    Doxygen's XML of the groups."""
    from breathe.renderer.sphinxrenderer import SphinxRenderer

    namespaces = {}
    for path in glob.glob(os.path.join(app.config.breathe_projects["tricell"], "group__*.xml")):
        for member in ElementTree.parse(path).iter("memberdef"):
            qualified = member.findtext("qualifiedname") or ""
            if "::" in qualified:
                namespaces[member.get("id")] = qualified.split("::")[:-1]
    plain = SphinxRenderer.get_qualification

    def get_qualification(self):
        names = plain(self)
        node = self.qualification_stack[0]
        if names or self.nesting_level > 0 or getattr(node, "node_type", None) != "memberdef":
            return names
        return list(namespaces.get(getattr(node, "id", None), []))

    SphinxRenderer.get_qualification = get_qualification


# Characters that start inline markup in reStructuredText (emphasis, literals, substitutions
# such as |D|, references such as max_); a backslash makes each stand for itself.
RST_MARKUP = re.compile(r"([\\*`|_])")


def plain_docstring(_app, _what, _name, _obj, _options, lines):
    """A docstring in reStructuredText that shows its plain text: prose paragraphs as one-line
    line blocks (reflowed, and no line of them read as a list, a table or a heading), indented
    paragraphs as literal blocks."""
    out = []
    for preformatted, text in paragraphs(list(lines)):
        if preformatted:
            out += ["::", ""] + ["    " + line for line in text] + [""]
        else:
            escaped = [RST_MARKUP.sub(r"\\\1", line.strip()) for line in text]
            out += ["| " + escaped[0]] + ["  " + line for line in escaped[1:]] + [""]
    lines[:] = out


def plain_signature(_app, _what, _name, _obj, _options, signature, return_annotation):
    """pybind11 writes an argument it takes as any object as `points: handle` and an untyped
    result as `-> object`; both are left out of the signature, which then reads as a call."""
    if signature:
        signature = re.sub(r": handle\b", "", signature)
    if return_annotation == "object":
        return_annotation = None
    return signature, return_annotation


def setup(app):
    app.connect("source-read", expand)
    app.connect("builder-inited", qualify_group_members)
    app.connect("autodoc-process-docstring", plain_docstring)
    app.connect("autodoc-process-signature", plain_signature)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
