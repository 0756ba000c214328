"""The Python snippets of README.md and docs/python.md run as written: every ```python block of
each file, in order and in one namespace (a later block may use an earlier one's names, as a
reader's session does), in a temporary directory that holds a link to the repository's scenes/
(the snippets name scene files relative to the repository's root). pandas, which a snippet
uses to show that a study's table is a mapping of columns, is no dependency: without it a
stand-in DataFrame takes its place and checks just that. A block that needs DOLFINx or MPI is
skipped with the reason (they run under mpirun, test_dolfinx.py)."""

import importlib.util
import re
import sys
import textwrap
import types
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
DOCUMENTS = ["README.md", "docs/python.md"]
BLOCK = re.compile(r"^([ \t]*)```python[ \t]*\n(.*?)^\1```[ \t]*$", re.M | re.S)
# Packages of the distributed route: a block importing one is skipped without it.
OPTIONAL = {"dolfinx", "mpi4py"}


def stand_in_pandas():
    """A module `pandas` whose DataFrame accepts what the snippet gives it only if it is a table
    of columns: a mapping from names to 1-D columns of one length."""

    def data_frame(columns):
        lengths = {name: len(column) for name, column in columns.items()}
        assert lengths and len(set(lengths.values())) == 1, lengths
        return columns

    return types.SimpleNamespace(DataFrame=data_frame)


def blocks(document):
    """The ```python blocks of `document`, dedented, in order."""
    text = (ROOT / document).read_text(encoding="utf-8")
    return [textwrap.dedent(m.group(2)) for m in BLOCK.finditer(text)]


def missing(code):
    """The optional packages `code` imports that are not installed."""
    imported = re.findall(r"^\s*(?:import|from)\s+([A-Za-z_]\w*)", code, re.M)
    return sorted(
        {m for m in imported if m in OPTIONAL and importlib.util.find_spec(m) is None}
    )


def test_both_documents_have_snippets():
    for document in DOCUMENTS:
        assert blocks(document), f"{document} has no ```python block"


SNIPPETS = [(d, i) for d in DOCUMENTS for i in range(len(blocks(d)))]


@pytest.mark.parametrize(
    "document,index", SNIPPETS, ids=[f"{d}#{i + 1}" for d, i in SNIPPETS]
)
def test_the_python_snippet_runs(document, index, tmp_path, monkeypatch):
    """Block `index` of `document` runs after the blocks before it, in one namespace."""
    code = blocks(document)[: index + 1]
    lacking = missing("\n".join(code))
    if lacking:
        pytest.skip(f"needs {', '.join(lacking)} (the distributed route), not installed here")
    if importlib.util.find_spec("pandas") is None:
        monkeypatch.setitem(sys.modules, "pandas", stand_in_pandas())
    (tmp_path / "scenes").symlink_to(ROOT / "scenes", target_is_directory=True)
    monkeypatch.chdir(tmp_path)
    namespace = {"__name__": "__snippet__"}
    for i, block in enumerate(code):
        exec(compile(block, f"{document}, python block {i + 1}", "exec"), namespace)
