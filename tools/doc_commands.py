#!/usr/bin/python3
"""The commands the README and docs/ show, and the names in them.

Reads every fenced shell block (```bash, ```sh, ```console, ```shell or an unmarked one) and
every inline code span that starts with a ROS command or ``bash``, and splits each command into
the names it claims exist: launch files and their arguments, the package's nodes, tools,
repository files, services and topics (with the launch file whose simulator the page started
before it: the name's context). ``test/unit/test_docs.py`` checks the names against the
repository, ``test/rostest/test_docs_walkthrough.py`` against a live simulator.
``python3 tools/doc_commands.py`` lists what it finds.
"""
import glob
import os
import re
import shlex
import sys
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
PKG = "epuck_vrep_compat"
SHELL_LANGUAGES = {"", "bash", "sh", "shell", "console"}
COMMAND_WORDS = {"roslaunch", "rosrun", "rostopic", "rosservice", "rosbag", "bash", "sudo",
                 "source", "catkin_make", "rosparam"}
OUTPUT_OPTIONS = {"-o", "-O", "--out", "--json", ">"}
SEPARATORS = {"|", "&&", "||", ";", ">", "&"}
PACKAGE_PATH = re.compile(r"\$\((?:rospack )?find " + PKG + r"\)")
# A repository file named in a command: a relative path with an ending the repository uses.
REPO_FILE = re.compile(r"^[\w.-]+(/[\w.-]+)+\.(py|yaml|launch|rviz|sh|urdf|cpp|test|md)$")
WALKTHROUGH_HEADING = "First walk-through"


@dataclass
class Command:
    """One command of a page: its words (shell-split, comment dropped) and where it stands."""
    page: str                  # path relative to the repository
    line: int                  # 1-based line in the page
    text: str                  # as written, continuation lines joined
    words: list
    heading: str               # the section it stands in
    fenced: bool               # in a fenced block (else an inline code span)
    context: "Command" = None  # the roslaunch before it on its page, if any

    def where(self):
        return f"{self.page}:{self.line}: {self.text}"


@dataclass
class Launch:
    """``roslaunch epuck_vrep_compat FILE a:=b ...``"""
    command: Command
    file: str
    args: dict = field(default_factory=dict)


@dataclass
class Name:
    """A topic or service a command names (``kind``: topic | service); ``msg_type`` where the
    command gives one (``rostopic pub /x TYPE``); ``values``: its other words."""
    command: Command
    kind: str
    name: str
    msg_type: str = None
    values: list = field(default_factory=list)


def doc_pages(repo=REPO):
    """README.md and docs/*.md, as paths relative to the repository."""
    pages = ["README.md"] + sorted(os.path.relpath(p, repo)
                                   for p in glob.glob(os.path.join(repo, "docs", "*.md")))
    return [p for p in pages if os.path.exists(os.path.join(repo, p))]


def fenced_blocks(text):
    """(language, first line number, lines, heading) of every fenced block."""
    heading, block, blocks = "", None, []
    for number, line in enumerate(text.split("\n"), 1):
        fence = re.match(r"^\s*```(\S*)\s*$", line)
        if block is None and fence:
            block = (fence.group(1).lower(), number + 1, [], heading)
        elif block is not None and re.match(r"^\s*```\s*$", line):
            blocks.append(block)
            block = None
        elif block is not None:
            block[2].append(line)
        elif line.startswith("#"):
            heading = line.lstrip("#").strip()
    return blocks


def shell_lines(first_line, lines):
    """(line number, command) of a shell block: continuations joined, prompts dropped."""
    joined, start, pending = [], None, ""
    for number, line in enumerate(lines, first_line):
        if not pending:
            start = number
            line = re.sub(r"^\s*\$ ", "", line)
        if line.rstrip().endswith("\\"):
            pending += line.rstrip()[:-1] + " "
            continue
        text = (pending + line).strip()
        pending = ""
        if text and not text.startswith("#"):
            joined.append((start, text))
    return joined


def split_words(text):
    """The shell words of one command line (the package's path as ``@pkg@``, comment dropped);
    None where the line cannot be shell (unbalanced quotes)."""
    text = PACKAGE_PATH.sub("@pkg@", text)
    try:
        lexer = shlex.shlex(text, posix=True, punctuation_chars="|&;>")
        lexer.whitespace_split = True
        lexer.commenters = "#"
        return list(lexer)
    except ValueError:
        return None


def simple_commands(words):
    """The words split at pipes, ``&&``, ``;`` and redirections: one list per command (a
    redirection's target stays with its command, after ``>``)."""
    commands, current = [], []
    for word in words:
        if word in SEPARATORS and word != ">":
            if current:
                commands.append(current)
            current = []
        else:
            current.append(word)
    if current:
        commands.append(current)
    return commands


def inline_spans(text):
    """(line number, code, heading) of the prose's inline code spans (single backticks, maybe
    across a line break) that start with a command word."""
    prose, headings, in_fence = [], [], False
    for number, line in enumerate(text.split("\n"), 1):
        if re.match(r"^\s*```", line):
            in_fence = not in_fence
            line = ""
        elif in_fence:
            line = ""
        elif line.startswith("#"):
            headings.append((number, line.lstrip("#").strip()))
        prose.append(line)
    prose = "\n".join(prose)
    found = []
    for match in re.finditer(r"(?<!`)`([^`]+)`(?!`)", prose):
        code = " ".join(match.group(1).split())
        first = code.split(" ", 1)[0]
        if first not in COMMAND_WORDS - {"source", "catkin_make"} or " " not in code:
            continue
        number = prose.count("\n", 0, match.start()) + 1
        heading = ([h for n, h in headings if n <= number] or [""])[-1]
        found.append((number, code, heading))
    return found


def page_commands(repo, page):
    """Every command of one page, in page order, each with its launch context."""
    text = open(os.path.join(repo, page), encoding="utf-8").read()
    found = []
    for language, first, lines, heading in fenced_blocks(text):
        if language in SHELL_LANGUAGES:
            found += [(n, t, heading, True) for n, t in shell_lines(first, lines)]
    found += [(n, t, h, False) for n, t, h in inline_spans(text)]
    commands, context = [], None
    for number, text_, heading, fenced in sorted(found, key=lambda c: c[0]):
        words = split_words(text_)
        if words is None:         # kept, without words: the docs test reports it
            commands.append(Command(page, number, text_, [], heading, fenced, context))
            continue
        for words_ in simple_commands(words):
            command = Command(page, number, text_, words_, heading, fenced, context)
            if launch_of(command):
                context = command
            commands.append(command)
    return commands


def all_commands(repo=REPO):
    return [c for page in doc_pages(repo) for c in page_commands(repo, page)]


def launch_of(command):
    """The Launch of ``roslaunch epuck_vrep_compat FILE a:=b ...``, else None."""
    w = command.words
    if len(w) < 3 or w[0] != "roslaunch" or w[1] != PKG:
        return None
    args = dict(word.split(":=", 1) for word in w[3:] if ":=" in word)
    return Launch(command, w[2], args)


def includes(launch_file, repo=REPO):
    """The package's launch files a launch file includes, itself first, recursively."""
    found, todo = [], [launch_file]
    while todo:
        name = todo.pop(0)
        path = os.path.join(repo, "launch", name)
        if name in found or not os.path.exists(path):
            continue
        found.append(name)
        todo += [os.path.basename(i.get("file"))
                 for i in ET.parse(path).getroot().iter("include")]
    return found


def node_of(command):
    """The node of ``rosrun epuck_vrep_compat NODE ...``, else None."""
    w = command.words
    return w[2] if len(w) >= 3 and w[0] == "rosrun" and w[1] == PKG else None


def tool_of(command):
    """The script of ``bash X`` (or ``sudo bash X``), else None."""
    w = command.words[1:] if command.words[:1] == ["sudo"] else command.words
    return w[1] if len(w) >= 2 and w[0] == "bash" else None


def names_of(command):
    """The topics and services a command names."""
    w = command.words
    if len(w) >= 3 and w[0] == "rostopic" and w[1] in ("pub", "echo", "hz", "info", "type", "bw"):
        names = [x for x in w[2:] if x.startswith("/")]
        if not names:
            return []
        rest = w[w.index(names[0]) + 1:]
        msg_type = rest[0] if w[1] == "pub" and rest and "/" in rest[0] else None
        return [Name(command, "topic", names[0], msg_type, rest[1:] if msg_type else rest)]
    if len(w) >= 3 and w[0] == "rosservice" and w[1] in ("call", "info", "type", "args"):
        return [Name(command, "service", w[2], None, w[3:])]
    if len(w) >= 3 and w[0] == "rosbag" and w[1] == "record":
        return [Name(command, "topic", x) for x in w[2:] if x.startswith("/")]
    return []


def repo_files_of(command):
    """Repository files a command names (outputs, after -o / --out / >, excepted)."""
    files = []
    for before, word in zip([None] + command.words, command.words):
        if before in OUTPUT_OPTIONS or ":=" in word:
            continue
        word = word.replace("@pkg@/", "")
        if REPO_FILE.match(word) and not word.startswith(".ws/"):
            files.append(word)
    return files


def links(repo=REPO):
    """(page, line, target) of every relative Markdown link of the pages."""
    found = []
    for page in doc_pages(repo):
        text = open(os.path.join(repo, page), encoding="utf-8").read()
        for match in re.finditer(r"\]\(([^)\s]+)\)", text):
            target = match.group(1)
            if not re.match(r"^[a-z]+:", target):
                found.append((page, text.count("\n", 0, match.start()) + 1, target))
    return found


def anchors(path):
    """GitHub's anchors of a Markdown file's headings."""
    slugs = set()
    for line in open(path, encoding="utf-8").read().split("\n"):
        if line.startswith("#"):
            title = line.lstrip("#").strip().lower()
            slugs.add(re.sub(r"[^\w\- ]", "", title).replace(" ", "-"))
    return slugs


def walkthrough(repo=REPO):
    """The README's first walk-through: its roslaunch (a Launch) and the command lines after
    it, in order (``source`` lines dropped), each as its list of simple commands."""
    commands = [c for c in page_commands(repo, "README.md")
                if c.fenced and c.heading == WALKTHROUGH_HEADING]
    launches = [launch_of(c) for c in commands if launch_of(c)]
    if len(launches) != 1:
        raise ValueError(f"README's '{WALKTHROUGH_HEADING}' starts {len(launches)} launch files")
    lines = {}
    for command in commands[commands.index(launches[0].command) + 1:]:
        if command.words[:1] != ["source"]:
            lines.setdefault(command.line, []).append(command)
    return launches[0], list(lines.values())


def main():
    for command in all_commands():
        extra = [f"{n.kind} {n.name}" for n in names_of(command)]
        context = f" [after {command.context.text}]" if command.context else ""
        print(command.where() + ("  -> " + ", ".join(extra) if extra else "") + context)
    return 0


if __name__ == "__main__":
    sys.exit(main())
