// rayunits report: index.html from index.md (issue 17 §4) — static and self-contained.
//
// The converter knows the Markdown the report writes: ATX headings, pipe tables (with the
// alignment row), fenced code blocks, `- ` and `1. ` lists, paragraphs, raw HTML lines (the
// section anchors `<a id=...></a>`), and inline `code`, **bold**, [links](href) and ![images](f).
// Images are embedded as data: URIs (PNG/SVG/JPEG read from the report directory), so the page
// needs no other file and no network. Tables sort by a click on a header (a small inline
// script). On load an inline script writes a verdict into <pre id="ru-verdict">: how many images
// decoded (naturalWidth > 0) of how many, and the ids of the h2 sections — the test reads it
// back from headless Chromium's --dump-dom.
#include <cctype>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "rayunits/report/report.hpp"

namespace ru::report {
namespace {

namespace fs = std::filesystem;

std::string esc(const std::string& s) {
  std::string o;
  for (char c : s) {
    switch (c) {
      case '&': o += "&amp;"; break;
      case '<': o += "&lt;"; break;
      case '>': o += "&gt;"; break;
      case '"': o += "&quot;"; break;
      default: o += c;
    }
  }
  return o;
}

std::string base64(const std::string& in) {
  static const char* t = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string o;
  std::size_t i = 0;
  for (; i + 2 < in.size(); i += 3) {
    const unsigned v = (unsigned char)in[i] << 16 | (unsigned char)in[i + 1] << 8 | (unsigned char)in[i + 2];
    o += t[v >> 18 & 63];
    o += t[v >> 12 & 63];
    o += t[v >> 6 & 63];
    o += t[v & 63];
  }
  if (i + 1 == in.size()) {
    const unsigned v = (unsigned char)in[i] << 16;
    o += t[v >> 18 & 63];
    o += t[v >> 12 & 63];
    o += "==";
  } else if (i + 2 == in.size()) {
    const unsigned v = (unsigned char)in[i] << 16 | (unsigned char)in[i + 1] << 8;
    o += t[v >> 18 & 63];
    o += t[v >> 12 & 63];
    o += t[v >> 6 & 63];
    o += '=';
  }
  return o;
}

struct Ctx {
  fs::path dir;
  std::vector<std::string>* missing;
};

std::string image(const std::string& alt, const std::string& src, const Ctx& c) {
  const fs::path p = c.dir / src;
  std::ifstream f(p, std::ios::binary);
  std::string mime = "image/png";
  const std::string ext = p.extension().string();
  if (ext == ".svg") mime = "image/svg+xml";
  else if (ext == ".jpg" || ext == ".jpeg") mime = "image/jpeg";
  if (!f) {
    c.missing->push_back(src);
    return "<img alt=\"" + esc(alt) + " (missing: " + esc(src) + ")\" src=\"\">";
  }
  std::ostringstream s;
  s << f.rdbuf();
  return "<img alt=\"" + esc(alt) + "\" title=\"" + esc(src) + "\" src=\"data:" + mime + ";base64," + base64(s.str()) +
         "\">";
}

// Inline markup of one line of text.
std::string inl(const std::string& s, const Ctx& c) {
  std::string o;
  for (std::size_t i = 0; i < s.size();) {
    if (s[i] == '`') {
      const auto e = s.find('`', i + 1);
      if (e != std::string::npos) {
        o += "<code>" + esc(s.substr(i + 1, e - i - 1)) + "</code>";
        i = e + 1;
        continue;
      }
    }
    if (s.compare(i, 2, "**") == 0) {
      const auto e = s.find("**", i + 2);
      if (e != std::string::npos) {
        o += "<strong>" + inl(s.substr(i + 2, e - i - 2), c) + "</strong>";
        i = e + 2;
        continue;
      }
    }
    const bool img = s.compare(i, 2, "![") == 0;
    if (img || s[i] == '[') {
      const std::size_t a = i + (img ? 2 : 1);
      const auto rb = s.find("](", a);
      const auto rp = rb == std::string::npos ? rb : s.find(')', rb + 2);
      if (rb != std::string::npos && rp != std::string::npos && s.find('\n', a) > rp) {
        const std::string text = s.substr(a, rb - a), href = s.substr(rb + 2, rp - rb - 2);
        if (img) o += image(text, href, c);
        else o += "<a href=\"" + esc(href) + "\">" + inl(text, c) + "</a>";
        i = rp + 1;
        continue;
      }
    }
    if (s[i] == '<') {  // raw inline HTML tags the report writes (<a id=...></a>, <br>)
      const auto e = s.find('>', i);
      const std::string tag = e == std::string::npos ? "" : s.substr(i, e - i + 1);
      if (tag.rfind("<a ", 0) == 0 || tag == "</a>" || tag == "<br>") {
        o += tag;
        i = e + 1;
        continue;
      }
    }
    o += esc(std::string(1, s[i]));
    ++i;
  }
  return o;
}

std::vector<std::string> cells(const std::string& line) {
  std::string t = line;
  while (!t.empty() && (t.back() == ' ' || t.back() == '\r')) t.pop_back();
  std::size_t b = t.find('|');
  std::vector<std::string> out;
  if (b == std::string::npos) return out;
  std::string cur;
  bool code = false;
  for (std::size_t i = b + 1; i < t.size(); ++i) {
    if (t[i] == '`') code = !code;
    if (t[i] == '|' && !code) {
      const auto f = cur.find_first_not_of(' '), l = cur.find_last_not_of(' ');
      out.push_back(f == std::string::npos ? "" : cur.substr(f, l - f + 1));
      cur.clear();
    } else {
      cur += t[i];
    }
  }
  return out;
}

bool is_rule(const std::string& line) {
  if (line.find('|') == std::string::npos || line.find('-') == std::string::npos) return false;
  for (char ch : line)
    if (ch != '|' && ch != '-' && ch != ':' && ch != ' ') return false;
  return true;
}

const char* kScript = R"JS(
function ruSort(th) {
  var table = th.closest('table'), idx = Array.prototype.indexOf.call(th.parentNode.children, th);
  var body = table.tBodies[0], rows = Array.prototype.slice.call(body.rows);
  var asc = th.getAttribute('data-asc') !== '1';
  th.setAttribute('data-asc', asc ? '1' : '0');
  function key(r) { var t = r.cells[idx] ? r.cells[idx].textContent.trim() : '';
                    var n = parseFloat(t.replace(/,/g, '')); return isNaN(n) ? t : n; }
  rows.sort(function (a, b) { var x = key(a), y = key(b);
    if (typeof x === typeof y) return (x < y ? -1 : x > y ? 1 : 0) * (asc ? 1 : -1);
    return (typeof x === 'number' ? -1 : 1) * (asc ? 1 : -1); });
  rows.forEach(function (r) { body.appendChild(r); });
}
window.addEventListener('load', function () {
  var imgs = document.images, ok = 0;
  for (var i = 0; i < imgs.length; i++) if (imgs[i].complete && imgs[i].naturalWidth > 0) ok++;
  var ids = [];
  document.querySelectorAll('a[id]').forEach(function (a) { ids.push(a.id); });
  var v = document.getElementById('ru-verdict');
  v.textContent = 'images ' + ok + '/' + imgs.length + '; sections ' + ids.join(',') +
                  (ok === imgs.length ? '; verdict ok' : '; verdict broken-images');
});
)JS";

}  // namespace

std::string markdown_to_html(const std::string& md, const std::filesystem::path& dir, const std::string& title,
                             std::vector<std::string>* missing_images) {
  std::vector<std::string> missing;
  Ctx c{dir, &missing};
  std::vector<std::string> lines;
  {
    std::istringstream in(md);
    for (std::string l; std::getline(in, l);) lines.push_back(l);
  }
  std::ostringstream o;
  o << "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>" << esc(title)
    << "</title>\n<style>\n"
       "body{font-family:sans-serif;max-width:80em;margin:1em auto;padding:0 1em;line-height:1.4}\n"
       "table{border-collapse:collapse;margin:.6em 0;font-size:90%}th,td{border:1px solid #ccc;padding:2px 6px}\n"
       "th{background:#f0f0f0;cursor:pointer}td.r{text-align:right}code{background:#f4f4f4;padding:0 2px}\n"
       "pre{background:#f4f4f4;padding:.5em;overflow-x:auto}img{max-width:100%}\n"
       "#ru-verdict{color:#888;font-size:80%}\n</style>\n</head>\n<body>\n";
  std::size_t i = 0;
  std::string para;
  auto flush = [&] {
    if (!para.empty()) o << "<p>" << inl(para, c) << "</p>\n";
    para.clear();
  };
  while (i < lines.size()) {
    const std::string& l = lines[i];
    if (l.rfind("```", 0) == 0) {
      flush();
      o << "<pre><code>";
      for (++i; i < lines.size() && lines[i].rfind("```", 0) != 0; ++i) o << esc(lines[i]) << "\n";
      o << "</code></pre>\n";
      ++i;
      continue;
    }
    if (l.empty()) {
      flush();
      ++i;
      continue;
    }
    std::size_t h = 0;
    while (h < l.size() && l[h] == '#') ++h;
    if (h >= 1 && h <= 6 && h < l.size() && l[h] == ' ') {
      flush();
      o << "<h" << h << ">" << inl(l.substr(h + 1), c) << "</h" << h << ">\n";
      ++i;
      continue;
    }
    if (l[0] == '|' && i + 1 < lines.size() && is_rule(lines[i + 1])) {
      flush();
      const auto head = cells(l), rule = cells(lines[i + 1]);
      o << "<table>\n<thead><tr>";
      for (const auto& x : head) o << "<th onclick=\"ruSort(this)\">" << inl(x, c) << "</th>";
      o << "</tr></thead>\n<tbody>\n";
      for (i += 2; i < lines.size() && !lines[i].empty() && lines[i][0] == '|'; ++i) {
        o << "<tr>";
        const auto row = cells(lines[i]);
        for (std::size_t k = 0; k < row.size(); ++k) {
          const bool right = k < rule.size() && !rule[k].empty() && rule[k].back() == ':';
          o << (right ? "<td class=\"r\">" : "<td>") << inl(row[k], c) << "</td>";
        }
        o << "</tr>\n";
      }
      o << "</tbody>\n</table>\n";
      continue;
    }
    const bool bullet = l.rfind("- ", 0) == 0;
    std::size_t d = 0;
    while (d < l.size() && std::isdigit(static_cast<unsigned char>(l[d]))) ++d;
    const bool numbered = d > 0 && l.compare(d, 2, ". ") == 0;
    if (bullet || numbered) {
      flush();
      o << (bullet ? "<ul>\n" : "<ol>\n");
      while (i < lines.size()) {
        const std::string& x = lines[i];
        std::size_t dd = 0;
        while (dd < x.size() && std::isdigit(static_cast<unsigned char>(x[dd]))) ++dd;
        std::string item;
        if (bullet && x.rfind("- ", 0) == 0) item = x.substr(2);
        else if (!bullet && dd > 0 && x.compare(dd, 2, ". ") == 0) item = x.substr(dd + 2);
        else if (!x.empty() && x[0] == ' ' && i > 0) {  // continuation line of an item
          o << " " << inl(x.substr(x.find_first_not_of(' ')), c);
          ++i;
          continue;
        } else break;
        o << "<li>" << inl(item, c);
        ++i;
      }
      o << (bullet ? "</ul>\n" : "</ol>\n");
      continue;
    }
    if (l.rfind("<a ", 0) == 0 || l.rfind("<div", 0) == 0) {  // raw HTML line
      flush();
      o << l << "\n";
      ++i;
      continue;
    }
    para += (para.empty() ? "" : "\n") + l;
    ++i;
  }
  flush();
  o << "<pre id=\"ru-verdict\">(the page's load script did not run)</pre>\n<script>" << kScript
    << "</script>\n</body>\n</html>\n";
  if (missing_images) *missing_images = missing;
  return o.str();
}

}  // namespace ru::report
