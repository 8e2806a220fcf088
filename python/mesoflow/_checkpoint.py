"""The resumable sweeps' checkpoint file (JSON lines), one rule for the clogging and the hopper sweeps:
the first line is the sweep's parameters (its signature), then one finished record per line, each
flushed and fsynced as it is written, so an interrupted sweep loses no finished record. Reopened
with the same signature it hands back the records it holds (an empty or torn last line, from a kill
while writing, is skipped); another signature raises ValueError naming what differs."""
import json
import os


class Checkpoint:
    """Checkpoint(path, signature): `records` holds what the file already has; append(record) adds one.
    path None keeps nothing."""

    def __init__(self, path, signature):
        self.records, self._out = [], None
        if path is None:
            return
        if os.path.exists(path):
            with open(path) as f:
                lines = f.read().split("\n")
            header = json.loads(lines[0])
            if header != signature:
                changed = sorted(k for k in set(header) | set(signature) if header.get(k) != signature.get(k))
                raise ValueError("checkpoint %s holds another sweep (differs in %s)" % (path, ", ".join(changed)))
            for line in lines[1:]:
                try:
                    self.records.append(json.loads(line))
                except ValueError:  # an empty or torn last line (killed while writing)
                    continue
        else:
            with open(path, "w") as f:
                f.write(json.dumps(signature) + "\n")
                f.flush()
                os.fsync(f.fileno())
        self._out = open(path, "a")

    def append(self, record):
        if self._out is not None:
            self._out.write(json.dumps(record) + "\n")
            self._out.flush()
            os.fsync(self._out.fileno())

    def close(self):
        if self._out is not None:
            self._out.close()
            self._out = None
