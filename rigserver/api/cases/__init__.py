"""What the routes do, apart from HTTP: load a run or a series (404 saying why), open and
end a run, write the students' words, correct a reading, store a posted batch, answer a
report. The API's routes and the pages' call these; no route module imports another."""
