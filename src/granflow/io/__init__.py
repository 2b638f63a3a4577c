"""Files a run writes: the run directory with atomic writes (run_dir), and the writers."""

from granflow.io.run_dir import CsvLog, RunDir, RunDirError

__all__ = ["CsvLog", "RunDir", "RunDirError"]
