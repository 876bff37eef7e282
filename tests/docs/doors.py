#!/usr/bin/env python3
"""The doors of the documentation: every command README.md and docs/*.md
tell a user to run, and every Python example of docs/*.md.

    doors.py list SRC            every door: FILE:LINE, its kind and its key
    doors.py check SRC           every door is run (run.txt) or listed with
                                 its reason (not-runnable.txt), and every
                                 entry of both is still a door
    doors.py get SRC RUNNER      the doors run.txt gives RUNNER, as the
                                 documents write them (see get())

A door is found, not declared:
- in a code block (4-space indented, or fenced with no language or a
  shell one), a line whose first word is a command (COMMANDS, a tool of
  ours, ./scripts/..., an assignment); in a block with "$ " prompts only
  the prompted lines (the rest is output);
- an inline `code span` in prose whose first word is a command and which
  has at least one argument;
- a fenced ```python block (its key: the first line that is not an
  import, a comment or blank);
- a fenced ```c block with a main(), which the prose before it names
  (`cc NAME.c`): its key is "c: NAME.c".
A door's key is its text with a trailing "# comment" dropped and runs of
white space made one space; the same key twice in one file is one door.
"""
import os
import re
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
TOOLS = {"sh2000ctl", "sh2000-sim", "sh2000-upload", "sh2000-tune", "sh2000-comp"}
COMMANDS = TOOLS | {
    "sudo", "cmake", "ctest", "cpack", "make", "apt", "apt-get", "dpkg",
    "dkms", "modprobe", "insmod", "rmmod", "depmod", "ldconfig", "groupadd",
    "usermod", "udevadm", "cp", "echo", "cc", "gcc", "pkg-config",
    "python3", "pytest", "linuxcnc", "halcmd", "halrun", "rs274", "nm",
    "export", "mkdir", "cd", "git", "chrt", "setcap", "tee"}
SHELL_FENCES = {"", "sh", "bash", "shell", "console"}


def doc_files(src):
    """README.md and docs/*.md, as paths relative to SRC."""
    docs = sorted(f for f in os.listdir(os.path.join(src, "docs"))
                  if f.endswith(".md"))
    return ["README.md"] + ["docs/" + f for f in docs]


def key_of(text):
    """A command's key: no trailing comment, white space runs made one."""
    text = re.sub(r"(^|\s)#\s.*$", "", text.strip())
    return " ".join(text.split())


def command_words(cmd, inline):
    """The words from the command word on: past "(", sudo and leading
    assignments. In a block a line of assignments is a command;
    inline, assignments alone (`io=`, `W=1`) name a setting."""
    words = cmd.lstrip("(").split()
    while words and (words[0] == "sudo" or
                     re.match(r"^[A-Za-z_][A-Za-z0-9_]*=", words[0])):
        if words[0] != "sudo" and not inline:
            return ["<assignment>"]
        words = words[1:]
    return words


def is_command(cmd, inline):
    """A line of a block (not indented: indented lines continue a
    synopsis or draw a diagram) or a code span that is a command."""
    if not inline and cmd[:1].isspace():
        return False
    words = command_words(cmd, inline)
    if not words:
        return False
    if words[0] == "<assignment>" or re.match(r"^(\./|scripts/)", words[0]):
        return True
    if words[0] not in COMMANDS:
        return False
    # inline: a word alone names a tool (unless given an environment),
    # and "python3 (>= 3.11~)" is a dependency; neither is a command
    if not inline:
        return True
    if len(words) == 1:
        return words[0] != cmd.lstrip("(").split()[0]
    return not words[1].startswith("(")


def blocks(lines):
    """(first line number, kind, [(line number, text)]) of each code block;
    kind is "shell", "python" or "other"."""
    out, i, n = [], 0, len(lines)
    while i < n:
        m = re.match(r"^```\s*(\w*)", lines[i])
        if m:
            lang, j = m.group(1), i + 1
            while j < n and not lines[j].startswith("```"):
                j += 1
            kind = ("shell" if lang in SHELL_FENCES else
                    lang if lang in ("python", "c") else "other")
            out.append((i + 1, kind, [(k + 1, lines[k]) for k in range(i + 1, j)]))
            i = j + 1
            continue
        if lines[i].startswith("    ") and (i == 0 or not lines[i - 1].strip()):
            j = i
            while j < n and (lines[j].startswith("    ") or
                             (not lines[j].strip() and j + 1 < n and
                              lines[j + 1].startswith("    "))):
                j += 1
            out.append((i + 1, "shell", [(k + 1, lines[k][4:]) for k in range(i, j)]))
            i = j
            continue
        i += 1
    return out


def block_doors(start, kind, body):
    """The doors of one code block: (line, kind, key, text, output); the
    output a "$ " transcript shows under its command, else None."""
    if kind == "python":
        code = "\n".join(t for _, t in body) + "\n"
        for _, t in body:
            if t.strip() and not re.match(r"^\s*(import |from |#)", t):
                return [(start, "python", "python: " + key_of(t), code, None)]
        return []
    if kind == "c":
        code = "\n".join(t for _, t in body) + "\n"
        return [(start, "c", None, code, None)] if "int main(" in code else []
    if kind != "shell":
        return []
    prompted = any(t.startswith("$ ") for _, t in body)
    doors, cur = [], None          # cur: [line, text, output lines]
    for ln, t in body:
        if cur and cur[1].endswith("\\"):      # a line continued with "\"
            cur[1] += "\n" + t
        elif prompted and t.startswith("$ "):
            cur = [ln, t[2:], []]
            doors.append(cur)
        elif prompted:
            if cur and t.strip():
                cur[2].append(t)
            elif cur:
                cur = None
        elif t.strip() and is_command(t, False):
            cur = [ln, t, []]
            doors.append(cur)
    return [(ln, "shell", key_of(t), t,
             "\n".join(out) + "\n" if prompted else None) for ln, t, out in doors]


def printed_by(lines, blist):
    """{python block's line: the text of the block it "prints"}: a python
    block, prose saying "prints", then an indented block of output."""
    out = {}
    for (s1, k1, b1), (s2, k2, b2) in zip(blist, blist[1:]):
        prose = " ".join(lines[b1[-1][0] + 1:s2 - 1]) if b1 else ""
        if k1 == "python" and k2 == "shell" and re.search(r"\bprints\b", prose) \
                and not block_doors(s2, k2, b2):
            out[s1] = "\n".join(t for _, t in b2) + "\n"
    return out


def inline_doors(lines, in_block):
    """Commands in `code spans` of the prose (a span may cross a line)."""
    prose = "\n".join("" if in_block[i] else l for i, l in enumerate(lines))
    doors = []
    for m in re.finditer(r"(?<!`)`([^`]+)`(?!`)", prose):
        text = " ".join(m.group(1).split())
        if is_command(text, True):
            ln = prose.count("\n", 0, m.start()) + 1
            doors.append((ln, "inline", key_of(text), text, None))
    return doors


def doors_of(src, rel):
    lines = open(os.path.join(src, rel), encoding="utf-8").read().split("\n")
    in_block = [False] * len(lines)
    found, blist = [], blocks(lines)
    prints = printed_by(lines, blist)
    for start, kind, body in blist:
        in_block[start - 1] = True
        for ln, _ in body:
            in_block[ln - 1] = True
        if body and start != body[0][0]:
            in_block[body[-1][0]] = True     # the closing fence
        for ln, k, key, text, output in block_doors(start, kind, body):
            if k == "c":        # named by the prose before it: `cc NAME.c`
                names = re.findall(r"`cc (\S+\.c)\b", "\n".join(lines[:start - 1]))
                key = "c: " + (names[-1] if names else "(no `cc NAME.c` before it)")
            found.append((ln, k, key, text, prints.get(start, output)))
    found += inline_doors(lines, in_block)
    return sorted(found)


def all_doors(src):
    """{(file, key): (first line, kind, text, output or None)}"""
    doors = {}
    for rel in doc_files(src):
        for ln, kind, key, text, output in doors_of(src, rel):
            doors.setdefault((rel, key), (ln, kind, text, output))
    return doors


def read_list(path):
    """Entries "FILE: KEY" of run.txt / not-runnable.txt: {(file, key):
    (section or reason, line)}. In run.txt "[RUNNER]" heads a section; in
    not-runnable.txt the indented lines under a group of entries are the
    reason of each entry of the group."""
    entries, section, group, reasoned = {}, None, [], False
    for n, line in enumerate(open(path, encoding="utf-8"), 1):
        line = line.rstrip("\n")
        if not line.strip() or line.startswith("#"):
            continue
        m = re.match(r"^\[([\w.-]+)\]", line)
        if m:
            section = m.group(1)
            continue
        if line[0].isspace():
            if not group:
                sys.exit(f"{path}:{n}: a reason with no entry above it")
            for e in group:
                entries[e] = ((entries[e][0] + " " + line.strip()).strip(), entries[e][1])
            reasoned = True
            continue
        f, sep, key = line.partition(": ")
        if not sep:
            sys.exit(f"{path}:{n}: not 'FILE: COMMAND'")
        e = (f, key.strip() if re.match(r"^(python|c): ", key) else key_of(key))
        if e in entries:
            sys.exit(f"{path}:{n}: {f}: '{key}' is listed twice")
        if reasoned:
            group, reasoned = [], False
        group.append(e)
        entries[e] = (section or "", n)
    return entries


def check(src):
    doors = all_doors(src)
    run = read_list(os.path.join(HERE, "run.txt"))
    skip = read_list(os.path.join(HERE, "not-runnable.txt"))
    bad = 0
    for d in sorted(set(run) & set(skip)):
        print(f"both run and not runnable: {d[0]}: {d[1]}")
        bad += 1
    for d, (why, n) in sorted(skip.items(), key=lambda e: e[1][1]):
        if not why.strip():
            print(f"not-runnable.txt:{n}: no reason given for {d[0]}: {d[1]}")
            bad += 1
    for name, lst in (("run.txt", run), ("not-runnable.txt", skip)):
        for d, (_, n) in sorted(lst.items(), key=lambda e: e[1][1]):
            if d not in doors:
                print(f"{name}:{n}: no longer in {d[0]}: {d[1]}")
                bad += 1
    for d, (ln, kind, _, _) in sorted(doors.items(), key=lambda e: (e[0][0], e[1][0])):
        if d not in run and d not in skip:
            print(f"{d[0]}:{ln}: {kind} door neither run (tests/docs/run.txt) "
                  f"nor listed (tests/docs/not-runnable.txt): {d[1]}")
            bad += 1
    print(f"{len(doors)} doors: {len(run)} run, {len(skip)} not runnable here, "
          f"{bad} problem(s)")
    return 1 if bad else 0


def get(src, runner):
    """The doors of RUNNER in run.txt's order, each as three fields ended
    by NUL: "FILE:LINE KIND" (KIND shell, inline, python or c:NAME.c),
    its text as the document writes it, and the output the document shows
    for it: "-" if none, else "+" and the lines."""
    doors = all_doors(src)
    run = read_list(os.path.join(HERE, "run.txt"))
    mine = sorted((n, d) for d, (sec, n) in run.items() if sec == runner)
    if not mine:
        sys.exit(f"run.txt: no door for runner '{runner}'")
    for n, d in mine:
        if d not in doors:
            sys.exit(f"run.txt:{n}: no longer in {d[0]}: {d[1]}")
        ln, kind, text, output = doors[d]
        output = "-" if output is None else "+" + output
        if kind == "c":
            kind += ":" + d[1][len("c: "):]     # c:NAME.c, the file to write
        sys.stdout.write(f"{d[0]}:{ln} {kind}\0{text}\0{output}\0")
    return 0


def main(argv):
    if len(argv) < 3 or argv[1] not in ("list", "check", "get"):
        sys.exit(__doc__)
    src = argv[2]
    if argv[1] == "list":
        for (f, key), (ln, kind, _, _) in sorted(all_doors(src).items(),
                                               key=lambda e: (e[0][0], e[1][0])):
            print(f"{f}:{ln}\t{kind}\t{key}")
        return 0
    if argv[1] == "check":
        return check(src)
    if len(argv) != 4:
        sys.exit(__doc__)
    return get(src, argv[3])


if __name__ == "__main__":
    sys.exit(main(sys.argv))
