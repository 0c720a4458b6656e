#include "esi/xml_schema.hpp"

#include <memory>
#include <string>

#include <libxml/parser.h>
#include <libxml/xmlerror.h>
#include <libxml/xmlschemas.h>
#include <libxml/xmlversion.h>

namespace ecat::esi {
namespace {

struct FirstError {
  bool seen = false;
  int line = 0;
  std::string message;
};

#if LIBXML_VERSION >= 21200
using ErrorPtr = const xmlError*;
#else
using ErrorPtr = xmlErrorPtr;
#endif

void collect(void* user, ErrorPtr error) {
  auto* first = static_cast<FirstError*>(user);
  if (first->seen || error == nullptr) return;
  first->seen = true;
  first->line = error->line;
  first->message = error->message ? error->message : "unknown error";
  while (!first->message.empty() &&
         (first->message.back() == '\n' || first->message.back() == ' ')) {
    first->message.pop_back();
  }
}

struct SchemaParserFree {
  void operator()(xmlSchemaParserCtxt* p) const { xmlSchemaFreeParserCtxt(p); }
};
struct SchemaFree {
  void operator()(xmlSchema* p) const { xmlSchemaFree(p); }
};
struct ValidFree {
  void operator()(xmlSchemaValidCtxt* p) const { xmlSchemaFreeValidCtxt(p); }
};
struct DocFree {
  void operator()(xmlDoc* p) const { xmlFreeDoc(p); }
};

// Routes libxml2's generic error output to `first` while alive, so nothing is
// printed to stderr.
class ErrorCapture {
 public:
  explicit ErrorCapture(FirstError& first) {
    xmlSetStructuredErrorFunc(&first, &collect);
  }
  ~ErrorCapture() { xmlSetStructuredErrorFunc(nullptr, nullptr); }
  ErrorCapture(const ErrorCapture&) = delete;
  ErrorCapture& operator=(const ErrorCapture&) = delete;
};

}  // namespace

struct SchemaValidator::Impl {
  std::unique_ptr<xmlSchema, SchemaFree> schema;
  std::string error;
};

SchemaValidator::SchemaValidator(std::string_view xsd) : impl_(std::make_unique<Impl>()) {
  xmlInitParser();  // idempotent; makes later use from several threads safe
  FirstError first;
  ErrorCapture capture(first);
  std::unique_ptr<xmlSchemaParserCtxt, SchemaParserFree> parser(
      xmlSchemaNewMemParserCtxt(xsd.data(), static_cast<int>(xsd.size())));
  if (parser) impl_->schema.reset(xmlSchemaParse(parser.get()));
  if (!impl_->schema) impl_->error = "schema: the device schema is invalid: " + first.message;
}

SchemaValidator::~SchemaValidator() = default;

Expected<void, LoadError> SchemaValidator::validate(std::string_view xml, std::string_view file_name) const {
  const std::string file(file_name);
  if (!impl_->schema) return fail(LoadError{file, 0, impl_->error});
  FirstError first;
  ErrorCapture capture(first);
  std::unique_ptr<xmlDoc, DocFree> doc(xmlReadMemory(xml.data(), static_cast<int>(xml.size()),
                                                     file.c_str(), nullptr, XML_PARSE_NONET));
  if (!doc) return fail(LoadError{file, first.line, "XML parse error: " + first.message});

  std::unique_ptr<xmlSchemaValidCtxt, ValidFree> valid(xmlSchemaNewValidCtxt(impl_->schema.get()));
  if (!valid) return fail(LoadError{file, 0, "schema: out of memory"});
  xmlSchemaSetValidStructuredErrors(valid.get(), &collect, &first);
  const int rc = xmlSchemaValidateDoc(valid.get(), doc.get());
  if (rc != 0 || first.seen) {
    return fail(LoadError{file, first.line,
                          "schema: " + (first.seen ? first.message : std::string("invalid"))});
  }
  return {};
}

}  // namespace ecat::esi
