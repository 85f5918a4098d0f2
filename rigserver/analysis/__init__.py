"""rigserver.analysis"""
