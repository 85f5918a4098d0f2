"""One module per lab work: the manual's tables and plots of a stand, from its results."""
