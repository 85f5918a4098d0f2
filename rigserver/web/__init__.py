"""rigserver.web"""
