"""Executes a notebook headless (nbclient) so that it cannot rot: `run_notebook.py NB.ipynb`.

The notebook runs in its own folder with the environment it is given (VERITY_REPORT names the
report to read); any cell error fails with the cell's traceback and exit status 1.
"""
import pathlib
import sys

import nbformat
from nbclient import NotebookClient

path = pathlib.Path(sys.argv[1])
nb = nbformat.read(path, as_version=4)
client = NotebookClient(nb, timeout=300, kernel_name="python3", resources={"metadata": {"path": str(path.parent)}})
client.execute()
for cell in nb.cells:
    for out in cell.get("outputs", []):
        if out.get("output_type") == "stream":
            sys.stdout.write(out.get("text", ""))
print(f"executed {path}: {len(nb.cells)} cells")
