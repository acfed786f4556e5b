"""The parts of a documentation page that the tests run: its fenced
blocks of one language and its ``$ `` command lines with their expected
exit codes (see ``test_docs``); ``test_machinery_example`` runs a page's
command lines too; the files a page names (conftest's shared commands
write them too).

A plain module, not fixtures. It imports by its plain name because pytest
puts this folder on ``sys.path`` (see ``conftest.py``)."""

from __future__ import annotations

import re


def blocks(text: str, lang: str) -> list[str]:
    """The contents of the text's ```{lang} fenced blocks."""
    return re.findall(rf"^```{lang}\n(.*?)^```", text, flags=re.S | re.M)


def commands(text: str) -> list[tuple[str, int]]:
    """The page's ``$ `` lines (continued lines joined) with their expected
    exit codes."""
    cmds = []
    for block in blocks(text, "console"):
        lines = block.splitlines()
        i = 0
        while i < len(lines):
            line = lines[i]
            if line.startswith("$ "):
                cmd = line[2:]
                while cmd.endswith("\\") and i + 1 < len(lines):      # continued lines
                    i += 1
                    cmd = cmd[:-1] + " " + lines[i].strip()
                m = re.search(r"#\s*exit (\d+)\b", cmd)
                cmds.append((cmd, int(m.group(1)) if m else 0))
            i += 1
    return cmds


def named_files(text: str) -> dict[str, str]:
    """The ```toml blocks that name their file on their first line."""
    files = {}
    for block in blocks(text, "toml"):
        m = re.match(r"# ([\w.-]+\.toml)\n", block)
        if m:
            files[m.group(1)] = block
    return files
