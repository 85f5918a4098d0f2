"""rigsim: simulated tribology stands that post readings to a real rigserver over HTTP."""
