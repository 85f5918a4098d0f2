"""Pydantic models of the wire and the results, shared by rigserver and rigsim."""
