"""rigserver: the data-acquisition and analysis service for tribology test stands."""
