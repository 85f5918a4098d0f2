-- wrk script of benchmarks/ingest.py: single-reading posts of the SMTs-2 friction record.
-- Run with one connection per thread (-tN -cN): thread k posts to the k-th run given, with
-- seq 0, 1, 2, ... and an increasing time, as one lab PC would.
--   wrk -t16 -c16 -d10s -s single.lua URL -- KEY RUN1,RUN2,...
-- done() prints one JSON line: requests, duration_us, errors, latency percentiles (us).

local threads = 0

function setup(thread)
  threads = threads + 1
  thread:set("index", threads)
end

function init(args)
  local runs = {}
  for id in string.gmatch(args[2], "[^,]+") do
    table.insert(runs, id)
  end
  path = "/api/v1/runs/" .. runs[(index - 1) % #runs + 1] .. "/readings"
  seq = 0
  wrk.headers["Authorization"] = "Bearer " .. args[1]
  wrk.headers["Content-Type"] = "application/json"
end

function request()
  local body = string.format(
    '{"seq":%d,"group":"friction","columns":{"time":[%d.5],"load":[300.0],' ..
    '"speed":[1000.0],"friction_moment":[2.5],"revolutions":[%d.0]}}',
    seq, seq, seq)
  seq = seq + 1
  return wrk.format("POST", path, nil, body)
end

function done(summary, latency, requests)
  local e = summary.errors
  io.write(string.format(
    '{"requests":%d,"duration_us":%d,"status_errors":%d,"socket_errors":%d,' ..
    '"p50_us":%d,"p99_us":%d}\n',
    summary.requests, summary.duration, e.status, e.connect + e.read + e.write + e.timeout,
    latency:percentile(50), latency:percentile(99)))
end
