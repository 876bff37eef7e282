# SPDX-License-Identifier: MIT
"""sh2000.Error: the one exception of the binding (no import of the
extension here: the extension imports this module to raise it)."""


class Error(Exception):
    """An error libsh2000 or libsh2000-motion reported.

    code     the library's code without its sign: an SH2000_E* value
             (sh2000.EPARAM, sh2000.EPROGRAM ...) or an errno number
    name     the code's name (sh2000_strerror)
    message  what failed and where, in the library's words
    where    "file:line[:column]" for errors in or while running an NC
             program, else None
    diagnostics  a program's errors and warnings, one formatted line each
    """

    def __init__(self, code, name, message, where=None):
        super().__init__(code, name, message, where)
        self.code = code
        self.name = name
        self.message = message
        self.where = where
        self.diagnostics = []

    def __str__(self):
        if self.where:
            return f"{self.where}: {self.message}"
        return self.message

    def __repr__(self):
        return (f"sh2000.Error(code={self.code}, name={self.name!r}, "
                f"message={self.message!r}, where={self.where!r})")
