# Writes INPUT (the web page) into OUTPUT as a C++ string constant.
file(READ ${INPUT} _text)
set(_delim "vlpground_page")
string(FIND "${_text}" ")${_delim}\"" _clash)
if(NOT _clash EQUAL -1)
  message(FATAL_ERROR "${INPUT} contains the raw-string delimiter )${_delim}\"")
endif()
file(WRITE ${OUTPUT} "// Generated from viz/web/index.html by viz/embed_page.cmake; do not edit.\n"
  "#include <string_view>\n"
  "namespace vlpground::viz::detail {\n"
  "extern const std::string_view kWebPage;\n"
  "const std::string_view kWebPage = R\"${_delim}(${_text})${_delim}\";\n"
  "}  // namespace vlpground::viz::detail\n")
