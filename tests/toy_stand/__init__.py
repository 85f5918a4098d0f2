"""A toy stand kind (a spring on a tensile tester), one module per layer: the test
``tests/test_toy_stand.py`` copies them into a copy of the packages and registers them."""
