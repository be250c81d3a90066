# Writes the C++ block that follows a marker in a document to a header, so that a test
# compiles the document's example as it stands (docs/contact-laws.md's example law, which
# tests/unit/test_example_law.cpp includes).
#   cmake -DDOC=<document.md> -DMARKER=<text of the marker line> -DOUT=<header> -P tests/doc_snippet.cmake
cmake_minimum_required(VERSION 3.25)

file(READ "${DOC}" text)
string(FIND "${text}" "${MARKER}" at)
if(at EQUAL -1)
  message(FATAL_ERROR "${DOC}: no line with '${MARKER}'")
endif()
string(SUBSTRING "${text}" ${at} -1 text)
set(fence "```cpp\n")
string(FIND "${text}" "${fence}" begin)
if(begin EQUAL -1)
  message(FATAL_ERROR "${DOC}: no ```cpp block after '${MARKER}'")
endif()
string(LENGTH "${fence}" skip)
math(EXPR begin "${begin} + ${skip}")
string(SUBSTRING "${text}" ${begin} -1 text)
string(FIND "${text}" "\n```" end)
if(end EQUAL -1)
  message(FATAL_ERROR "${DOC}: the ```cpp block after '${MARKER}' does not end")
endif()
string(SUBSTRING "${text}" 0 ${end} code)
file(WRITE "${OUT}" "// Written from ${DOC} by tests/doc_snippet.cmake: edit the document, not this file.\n${code}\n")
