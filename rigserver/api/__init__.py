"""rigserver.api"""
