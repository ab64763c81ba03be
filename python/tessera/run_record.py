"""run.json in an output folder from Python: the C++ drivers' io::run_record (DESIGN.md §8).

    with tessera.run_record("results/tension", "direct_tension.py", sys.argv[1:]) as record:
        ...                                   # run.json says "running"
        write_curve(record.file("curve.csv"))  # each output listed as it is named
    # run.json: "complete"; "interrupted" after Ctrl-C (KeyboardInterrupt), "failed" after any other exception

The keys are the C++ record's: program, version, commit, arguments, status, started_unix_s,
files. Entering the record creates the folder and first removes the plain files an earlier
run.json there lists (only plain names inside the folder), as the C++ record does; run.json is
replaced atomically (written beside it, then renamed). The exception is never swallowed.
"""
import os
import time

from ._build import COMMIT
from ._tessera import InvalidInput, __version__


class run_record:
    """run.json of one run in folder `out` (see the module comment); a context manager."""

    def __init__(self, out, program, arguments=()):
        self.out = os.fspath(out)
        self.program = str(program)
        self.arguments = [str(a) for a in arguments]
        self.files = []
        self.started = 0
        self.status = None

    def __enter__(self):
        os.makedirs(self.out, exist_ok=True)
        self._remove_earlier_outputs()
        self.started = int(time.time())
        self._write("running")
        return self

    def __exit__(self, kind, value, traceback):
        if kind is None:
            self._write("complete")
        elif issubclass(kind, KeyboardInterrupt):
            self._write("interrupted")
        else:
            self._write("failed")
        return False  # the exception, if any, goes on

    def file(self, name):
        """Lists the plain file name `name` in run.json and returns its path in the folder."""
        if os.path.basename(name) != name or name in ("", ".", "..", "run.json"):
            raise InvalidInput("run_record.file: %r is not a plain file name other than run.json" % (name,))
        if name not in self.files:
            self.files.append(name)
            self._write("running")
        return os.path.join(self.out, name)

    def _write(self, status):
        import json  # here, not at the top: `import tessera` stays light

        self.status = status
        text = json.dumps({"program": self.program, "version": __version__, "commit": COMMIT,
                           "arguments": self.arguments, "status": status,
                           "started_unix_s": self.started, "files": self.files}, indent=2) + "\n"
        path = os.path.join(self.out, "run.json")
        with open(path + ".tmp", "w") as f:
            f.write(text)
        os.replace(path + ".tmp", path)

    def _remove_earlier_outputs(self):
        import json

        try:
            with open(os.path.join(self.out, "run.json")) as f:
                earlier = json.load(f).get("files", [])
        except (OSError, ValueError, AttributeError):
            return
        for name in earlier if isinstance(earlier, list) else []:
            if isinstance(name, str) and name and os.path.basename(name) == name and name not in (".", ".."):
                path = os.path.join(self.out, name)
                if os.path.isfile(path):
                    os.remove(path)
