"""rigserver.storage"""
