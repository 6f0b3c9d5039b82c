# The Python blocks of docs/python.md run as written, from the repository root.
import re


def test_python_md_example_runs(root, monkeypatch, capsys):
    text = (root / "docs/python.md").read_text()
    blocks = re.findall(r"```python\n(.*?)```", text, re.S)
    assert blocks, "docs/python.md has no ```python block"
    monkeypatch.chdir(root)
    for code in blocks:
        exec(compile(code, "docs/python.md", "exec"), {})
    out = capsys.readouterr().out
    assert "[1.675 1.5  ]" in out and "tracking" in out
    assert "tracking 1.3 1.75 2000 (6, 6) 0" in out  # the polyloc.shm example
