"""docs/designing-a-study.md, section 0, run as written: the campaign file it shows, the
commands it shows (argument vectors, no shell), and the lines it says they print. A change of
the printed range, the question or a verdict row makes the page wrong, and this test fail.
Beyond the page: checks.json records the question asked, and every verdict of the range asked
judges inside it.
"""
import json
import re
import shlex
import subprocess

import pytest

MARK = re.compile(r"<!-- walkthrough: (file (\S+)|run|output of (\d+)) -->\n```[a-z]*\n(.*?)```",
                  re.S)


def walkthrough(source):
    """The page's files, commands and expected lines, in the page's order."""
    text = (source / "docs" / "designing-a-study.md").read_text()
    files, commands, outputs = {}, [], {}
    for m in MARK.finditer(text):
        body = m.group(4)
        if m.group(2):
            files[m.group(2)] = body
        elif m.group(1) == "run":
            commands += [shlex.split(line) for line in body.splitlines() if line.strip()]
        else:
            outputs[int(m.group(3))] = [line.rstrip() for line in body.splitlines() if line.strip()]
    return files, commands, outputs


def test_the_page_has_a_walkthrough(source):
    files, commands, outputs = walkthrough(source)
    assert "mine.toml" in files
    assert [c[:3] for c in commands] == [["build/jam", "campaign", "plan"],
                                         ["build/jam", "pipeline", "mine.toml"]]
    assert set(outputs) == {1, 2}


def test_the_walkthrough_prints_what_the_page_says(jam, source, tmp_path):
    files, commands, outputs = walkthrough(source)
    for name, body in files.items():
        (tmp_path / name).write_text(body)
    printed = []
    for argv in commands:
        assert argv[0] == "build/jam", argv
        run = subprocess.run([str(jam)] + argv[1:], cwd=tmp_path, capture_output=True, text=True,
                             timeout=600)
        assert run.returncode == 0, (argv, run.stdout, run.stderr)
        printed.append([line.rstrip() for line in (run.stdout + run.stderr).splitlines()])
    for k, expected in outputs.items():
        missing = [line for line in expected if line not in printed[k - 1]]
        assert not missing, ("the page's lines not printed by command", k, missing,
                             "\n".join(printed[k - 1]))

    judged = json.loads((tmp_path / "runs" / "mine" / "checks.json").read_text())
    question = judged["question"]
    assert question["range"]["phi_min"] == 0.835 and question["range"]["phi_max"] == 0.85
    assert question["checks"] == ["finite_size"] and question["alpha"] == 0.05
    asked = [v for v in judged["verdicts"] if v.get("region") == "asked"]
    assert len(asked) == 2, asked  # constant phi and constant Z
    at_phi = [v for v in asked if v["range_variable"] == "phi"]
    assert len(at_phi) == 1
    assert 0.835 <= at_phi[0]["values"]["range_min"] < at_phi[0]["values"]["range_max"] <= 0.85
    assert at_phi[0]["table"]["range"] == "phi 0.836..0.85"
