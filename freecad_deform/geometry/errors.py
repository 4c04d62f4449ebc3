"""The one error type a kernel raises for bad input."""


class DeformError(ValueError):
    """Input that cannot give a valid result.

    `prop` names the property (CamelCase, as on the document object) the user should
    change; the message is one sentence that says what is wrong and what to do.
    """

    def __init__(self, message, prop=None):
        super().__init__(message)
        self.prop = prop
