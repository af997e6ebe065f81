"""capz.Error: what the library's capz::Error becomes in Python."""


class Error(Exception):
    """A capz error: ``code`` names the kind of fault as the command line does, ``message``
    says what is wrong (naming the file), ``exit_status`` is the status ``capz`` would exit with.

    Codes: usage (1), io (2), not-our-format (3), unsupported-version (4), corrupt (5),
    invalid-parameter (6), internal (7), memory-limit (8); see docs/CLI.md.
    """

    def __init__(self, code: str, message: str, exit_status: int = 0) -> None:
        super().__init__(message)
        self.code = code
        self.message = message
        self.exit_status = exit_status

    def __reduce__(self):  # so it crosses process boundaries (multiprocessing) intact
        return (Error, (self.code, self.message, self.exit_status))

    def __str__(self) -> str:
        return f"{self.message} [{self.code}]"
