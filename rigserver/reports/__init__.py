"""rigserver.reports"""
